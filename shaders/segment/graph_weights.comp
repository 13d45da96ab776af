#version 450
// Affinity of each kNN edge: exp(-beta_c |rgb_i - rgb_j|^2) * exp(-(d / (beta_d s))^2)
// * exp(-beta_n f_i f_j (1 - (n_i . n_j)^2)) * min(opacity_i, opacity_j)^beta_o, with s the geometric
// mean of the two nodes' local spacings (a sparse Gaussian's long edge into a dense part stays
// weak: floaters do not bridge objects) and f their flatness (a round Gaussian has no normal).
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Pos { vec4 pos[]; };
layout(std430, binding = 1) readonly buffer Colour { vec4 colour[]; };
layout(std430, binding = 2) readonly buffer Normal { vec4 normal[]; };
layout(std430, binding = 3) readonly buffer Nbr { uint nbr[]; };
layout(std430, binding = 4) readonly buffer Dist { float dist[]; };
layout(std430, binding = 5) readonly buffer Spacing { float spacing[]; };
layout(std430, binding = 6) writeonly buffer Weight { float weight[]; };  // per kNN slot, 0 when empty
layout(push_constant) uniform Push { GraphWeightsPush pc; };

void main() {
    uint e = pg_global_index();
    if (e >= pc.size.x * pc.size.y) return;
    uint i = e / pc.size.y, j = nbr[e];
    if (j == kGraphNone) {
        weight[e] = 0.0;
        return;
    }
    vec3 dc = colour[i].rgb - colour[j].rgb;
    float s = max(sqrt(spacing[i] * spacing[j]), 1e-12) * pc.beta.z;
    float r = dist[e] / s;
    float nn = dot(normal[i].xyz, normal[j].xyz);
    float bend = normal[i].w * normal[j].w * (1.0 - nn * nn);
    weight[e] = exp(-pc.beta.x * dot(dc, dc) - r * r - pc.beta.y * bend) * pow(max(min(pos[i].w, pos[j].w), 1e-30), pc.beta.w);
}

#version 450
// Affinity of each kNN edge: exp(-beta_c |rgb_i - rgb_j|^2) * exp(-(d / (beta_d s))^2)
// * exp(-beta_n f_i f_j (1 - (n_i . n_j)^2)) * min(opacity_i, opacity_j)^beta_o, with s the geometric
// mean of the two nodes' local spacings (a sparse Gaussian's long edge into a dense part stays
// weak: floaters do not bridge objects) and f their flatness (a round Gaussian has no normal).
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"

layout(local_size_x = 256) in;
// Reads through texel buffers: gathered in vector code on CPU drivers (graph_knn.comp).
layout(binding = 0, rgba32f) readonly uniform imageBuffer pos;
layout(binding = 1, rgba32f) readonly uniform imageBuffer colour;
layout(binding = 2, rgba32f) readonly uniform imageBuffer normal;
layout(binding = 3, r32ui) readonly uniform uimageBuffer nbr;
layout(binding = 4, r32f) readonly uniform imageBuffer dist;
layout(binding = 5, r32f) readonly uniform imageBuffer spacing;
layout(std430, binding = 6) writeonly buffer Weight { float weight[]; };  // per kNN slot, 0 when empty
layout(push_constant) uniform Push { GraphWeightsPush pc; };

void main() {
    uint e = pg_global_index();
    if (e >= pc.size.x * pc.size.y) return;
    uint i = e / pc.size.y, j = imageLoad(nbr, int(e)).x;
    if (j == kGraphNone) {
        weight[e] = 0.0;
        return;
    }
    vec3 dc = imageLoad(colour, int(i)).rgb - imageLoad(colour, int(j)).rgb;
    float s = max(sqrt(imageLoad(spacing, int(i)).x * imageLoad(spacing, int(j)).x), 1e-12) * pc.beta.z;
    float r = imageLoad(dist, int(e)).x / s;
    const vec4 ni = imageLoad(normal, int(i)), nj = imageLoad(normal, int(j));
    float nn = dot(ni.xyz, nj.xyz);
    float bend = ni.w * nj.w * (1.0 - nn * nn);
    const float oi = imageLoad(pos, int(i)).w, oj = imageLoad(pos, int(j)).w;
    weight[e] = exp(-pc.beta.x * dot(dc, dc) - r * r - pc.beta.y * bend) * pow(max(min(oi, oj), 1e-30), pc.beta.w);
}

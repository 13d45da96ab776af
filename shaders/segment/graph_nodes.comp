#version 450
// Gathers the domain's Gaussians into the graph's node attributes: position and opacity,
// colour from the SH DC term, and the normal of the flattest axis with how flat it is.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Means { vec4 means[]; };    // xyz, opacity logit
layout(std430, binding = 1) readonly buffer Shapes { vec4 shapes[]; };  // [2i]: log-scale, [2i+1]: quat wxyz
layout(std430, binding = 2) readonly buffer Coeffs { float sh[]; };
layout(std430, binding = 3) readonly buffer Domain { uint domain[]; };  // scene index per node
layout(std430, binding = 4) writeonly buffer Pos { vec4 pos[]; };       // xyz, opacity
layout(std430, binding = 5) writeonly buffer Colour { vec4 colour[]; }; // rgb, unused
layout(std430, binding = 6) writeonly buffer Normal { vec4 normal[]; }; // unit axis, w: flatness in [0, 1]
layout(push_constant) uniform Push { GraphNodesPush pc; };

const float kShC0 = 0.28209479177387814;

void main() {
    uint i = pg_global_index();
    if (i >= pc.size.x) return;
    uint g = domain[i];
    vec4 m = means[g];
    pos[i] = vec4(m.xyz, 1.0 / (1.0 + exp(-m.w)));
    uint base = g * pc.size.y;
    vec3 dc = pc.size.z != 0u
        ? vec3(unpackHalf2x16(floatBitsToUint(sh[base])), unpackHalf2x16(floatBitsToUint(sh[base + 1u])).x)
        : vec3(sh[base], sh[base + 1u], sh[base + 2u]);
    colour[i] = vec4(clamp(vec3(0.5) + kShC0 * dc, 0.0, 1.0), 0.0);

    vec3 s = shapes[2u * g].xyz;
    vec4 q = shapes[2u * g + 1u];
    q /= max(length(q), 1e-20);
    float w = q.x, x = q.y, y = q.z, z = q.w;
    // Columns of the rotation: the Gaussian's axes in world space.
    vec3 c0 = vec3(1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y + w * z), 2.0 * (x * z - w * y));
    vec3 c1 = vec3(2.0 * (x * y - w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z + w * x));
    vec3 c2 = vec3(2.0 * (x * z + w * y), 2.0 * (y * z - w * x), 1.0 - 2.0 * (x * x + y * y));
    int a = s.x <= s.y ? (s.x <= s.z ? 0 : 2) : (s.y <= s.z ? 1 : 2);
    float smallest = s[a];
    float middle = a == 0 ? min(s.y, s.z) : (a == 1 ? min(s.x, s.z) : min(s.x, s.y));
    vec3 n = a == 0 ? c0 : (a == 1 ? c1 : c2);
    // Log scales: a disc 10x thinner than wide is flat (1), a ball is not (0).
    float flat_ = clamp((middle - smallest) / log(10.0), 0.0, 1.0);
    normal[i] = vec4(normalize(n), flat_);
}

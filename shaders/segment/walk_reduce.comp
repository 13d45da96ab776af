#version 450
// One workgroup per vec4 of columns: sums the node passes' partial dots and updates the
// columns' scalars. mode.x = 0: r.z at the start; 1: alpha = r.z / p.Ap; 2: beta = r.z' / r.z;
// 3: b.b/diag, the scale of the problem (the stop test compares r.z with it).
// A column whose residual is gone gets alpha = beta = 0 and stays where it is.
#extension GL_GOOGLE_include_directive : require
#include "segment/graph_shared.h"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Partials { vec4 partials[]; };
layout(std430, binding = 1) buffer Scalars { WalkScalars scalars[]; };  // kWalkMaxLabels
layout(push_constant) uniform Push { WalkPush pc; };

shared vec4 s_sum[256];

void main() {
    uint c = gl_WorkGroupID.x, groups = pc.size.w, t = gl_LocalInvocationIndex;
    vec4 sum = vec4(0.0);
    for (uint g = t; g < groups; g += 256u) sum += partials[g * kWalkVecs + c];
    s_sum[t] = sum;
    barrier();
    for (uint stride = 128u; stride > 0u; stride >>= 1) {
        if (t < stride) s_sum[t] += s_sum[t + stride];
        barrier();
    }
    if (t >= 4u) return;
    float total = s_sum[0][t];
    uint l = 4u * c + t;
    vec4 s = scalars[l].value;
    if (pc.mode.x == 0u) s.xyz = vec3(total, 0.0, 0.0);
    else if (pc.mode.x == 3u) s.w = total;
    else if (pc.mode.x == 1u) s.y = total > 0.0 && s.x > 0.0 ? s.x / total : 0.0;
    else {
        s.z = s.x > 0.0 ? total / s.x : 0.0;
        s.x = total;
    }
    scalars[l].value = s;
}

#version 450
// y[m, c] = max of x[member, c] over the members of cluster m; one invocation per output.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/index_shared.glsl"
layout(local_size_x = PG_INDEX_THREADS) in;
layout(std430, binding = 0) readonly buffer X { float x[]; };
layout(std430, binding = 1) readonly buffer Members { int members[]; };
layout(std430, binding = 2) readonly buffer Ptr { int ptr[]; };
layout(std430, binding = 3) writeonly buffer Y { float y[]; };
layout(push_constant) uniform PushBlock { SegmentMaxPush pc; };

void main() {
    uint e = pg_global_index();
    if (e >= pc.clusters * pc.channels) return;
    uint m = e / pc.channels, c = e - m * pc.channels;
    int begin = ptr[m], end = ptr[m + 1u];
    float best = x[uint(members[begin]) * pc.channels + c];
    for (int j = begin + 1; j < end; ++j) best = max(best, x[uint(members[j]) * pc.channels + c]);
    y[e] = best;
}

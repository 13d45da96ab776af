#version 450
// Backward of the cluster max (nn/segment_max): dy[m, c] goes to the member holding the max of
// channel c, the lowest point index among ties; the other members get 0. Clusters partition the
// points, so each dx entry is written exactly once. One invocation per (cluster, channel).
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/grad_shared.glsl"
layout(local_size_x = PG_GRAD_THREADS) in;
layout(std430, binding = 0) readonly buffer XBuf { float x[]; };
layout(std430, binding = 1) readonly buffer DyBuf { float dy[]; };
layout(std430, binding = 2) readonly buffer MembersBuf { int members[]; };
layout(std430, binding = 3) readonly buffer PtrBuf { int ptr[]; };
layout(std430, binding = 4) writeonly buffer DxBuf { float dx[]; };
layout(push_constant) uniform PushBlock { GroupPush pc; };  // targets = clusters

void main() {
    const uint e = pg_global_index();
    if (e >= pc.targets * pc.cols) return;
    const uint m = e / pc.cols, c = e % pc.cols;
    const int begin = ptr[m], end = ptr[m + 1u];
    int best = members[begin];
    float best_v = x[uint(best) * pc.cols + c];
    for (int j = begin + 1; j < end; ++j) {
        const int p = members[j];
        const float v = x[uint(p) * pc.cols + c];
        if (v > best_v || (v == best_v && p < best)) {
            best = p;
            best_v = v;
        }
    }
    const float g = dy[e];
    for (int j = begin; j < end; ++j) {
        const int p = members[j];
        dx[uint(p) * pc.cols + c] = p == best ? g : 0.0;
    }
}

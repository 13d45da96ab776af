#version 450
// k-means update, second half, per window: each cluster coordinate's sum over the window (its
// `whole` sum, or its first chunk's tail plus the heads of the chunks its run reaches, in
// order) is added to the running sum over windows, with Kahan compensation, and its member
// count to the running count. Windows run in point order, so the order is fixed.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "compress/kmeans_shared.h"

layout(local_size_x = PG_KMEANS_THREADS) in;
layout(std430, binding = 0) readonly buffer Start { uint start[]; };
layout(std430, binding = 1) readonly buffer End { uint end_[]; };
layout(std430, binding = 2) readonly buffer Whole { float whole[]; };
layout(std430, binding = 3) readonly buffer Head { float head[]; };
layout(std430, binding = 4) readonly buffer Tail { float tail[]; };
layout(std430, binding = 5) buffer Sum { float sum[]; };      // k x dims, over the windows so far
layout(std430, binding = 6) buffer Carry { float carry[]; };  // its Kahan compensation
layout(std430, binding = 7) buffer Count { uint count[]; };   // k
layout(push_constant) uniform Push { KmeansClusterPush pc; };

void main() {
    const uint t = pg_global_index();
    if (t >= pc.k * pc.dims) return;
    const uint c = t / pc.dims, d = t % pc.dims;
    const uint s = start[c], e = end_[c];
    if (e <= s) return;
    const uint first = s / PG_KMEANS_CHUNK, last = (e - 1u) / PG_KMEANS_CHUNK;
    precise float w;
    if (first == last) {
        w = whole[t];
    } else {
        precise float c2 = 0.0;
        w = tail[first * pc.dims + d];
        for (uint q = first + 1u; q <= last; ++q) {
            precise float y = head[q * pc.dims + d] - c2;
            precise float next = w + y;
            c2 = (next - w) - y;
            w = next;
        }
    }
    precise float y = w - carry[t];
    precise float next = sum[t] + y;
    carry[t] = (next - sum[t]) - y;
    sum[t] = next;
    if (d == 0u) count[c] += e - s;
}

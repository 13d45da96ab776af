#version 450
// k-means update, first half: the sorted members of a window are cut into chunks of
// PG_KMEANS_CHUNK; one invocation per (chunk, coordinate) walks its chunk in order and sums
// each cluster's piece of it with Kahan compensation. A cluster whose run lies inside the chunk
// is done: its sum goes to `whole`. A run that crosses a chunk border leaves pieces for
// kmeans_accumulate: the one that continues an earlier chunk's run is the chunk's `head`, the
// one that goes on into the next chunk its `tail` (a run through the whole chunk is its head).
// Bounded loops and a fixed order: no atomics, the same bytes on every run.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "compress/kmeans_shared.h"

layout(local_size_x = PG_KMEANS_THREADS) in;
layout(std430, binding = 0) readonly buffer Keys { uint keys[]; };        // labels, sorted
layout(std430, binding = 1) readonly buffer Members { uint members[]; };  // their points, in point order per label
layout(std430, binding = 2) readonly buffer Points { float points[]; };   // the window's points
layout(std430, binding = 3) writeonly buffer Whole { float whole[]; };    // k x dims
layout(std430, binding = 4) writeonly buffer Head { float head[]; };      // chunks x dims
layout(std430, binding = 5) writeonly buffer Tail { float tail[]; };      // chunks x dims
layout(push_constant) uniform Push { KmeansPiecePush pc; };

void main() {
    const uint t = pg_global_index();
    if (t >= pc.chunks * pc.dims) return;
    const uint q = t / pc.dims, d = t % pc.dims;
    const uint begin = q * PG_KMEANS_CHUNK, end = min(pc.n, begin + PG_KMEANS_CHUNK);
    bool continues = begin > 0u && keys[begin - 1u] == keys[begin];  // the first piece's run began earlier
    precise float sum = 0.0, carry = 0.0;
    for (uint j = begin; j < end; ++j) {
        precise float y = points[members[j] * pc.dims + d] - carry;
        precise float next = sum + y;
        carry = (next - sum) - y;
        sum = next;
        const uint key = keys[j];
        const bool last = j + 1u == end || keys[j + 1u] != key;
        if (last) {
            const bool goes_on = j + 1u < pc.n && keys[j + 1u] == key;
            if (continues)
                head[t] = sum;
            else if (goes_on)
                tail[t] = sum;
            else
                whole[key * pc.dims + d] = sum;
            continues = false;
            sum = 0.0;
            carry = 0.0;
        }
    }
}

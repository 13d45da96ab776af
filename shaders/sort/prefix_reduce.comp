#version 450
// Prefix sum, first level: the sum of each block of PG_SORT_BLOCK values.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "sort/sort_config.h"
layout(local_size_x = PG_SORT_THREADS) in;
layout(std430, binding = 0) readonly buffer In { uint values[]; };
layout(std430, binding = 1) writeonly buffer Sums { uint sums[]; };
layout(push_constant) uniform PushBlock { PrefixPush pc; };
#include "sort/block_scan.glsl"

void main() {
    uint b = pg_group_index();
    uint begin = b * PG_SORT_BLOCK;
    if (begin >= pc.n) return;
    uint t = gl_LocalInvocationIndex;
    uint sum = 0u;
    for (uint i = 0u; i < PG_SORT_ITEMS; ++i) {
        uint e = begin + i * PG_SORT_THREADS + t;  // coalesced: order does not matter for a sum
        if (e < pc.n) sum += values[e];
    }
    uint total;
    pg_block_exclusive_scan(sum, total);
    if (t == 0u) sums[pc.block_offset + b] = total;
}

#version 450
// Prefix sum, last level: exclusive scan of each block of PG_SORT_BLOCK values, plus the
// block's offset from the scanned block sums. In place is allowed (In and Out the same):
// every invocation reads its values before the block scan and writes them after it.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "sort/sort_config.h"
layout(local_size_x = PG_SORT_THREADS) in;
layout(std430, binding = 0) readonly buffer In { uint values[]; };
layout(std430, binding = 1) writeonly buffer Out { uint result[]; };
layout(std430, binding = 2) readonly buffer Sums { uint sums[]; };
layout(std430, binding = 3) writeonly buffer Total { uint total_out[]; };
layout(push_constant) uniform PushBlock { PrefixPush pc; };
#include "sort/block_scan.glsl"

void main() {
    uint b = pg_group_index();
    uint begin = b * PG_SORT_BLOCK;
    if (begin >= pc.n) return;
    uint t = gl_LocalInvocationIndex;
    // Each invocation owns a contiguous run, so its serial sum is in order.
    uint first = begin + t * PG_SORT_ITEMS;
    uint v[PG_SORT_ITEMS];
    uint sum = 0u;
    for (uint i = 0u; i < PG_SORT_ITEMS; ++i) {
        v[i] = first + i < pc.n ? values[first + i] : 0u;
        sum += v[i];
    }
    uint total;
    uint run = pg_block_exclusive_scan(sum, total);
    uint offset = (pc.flags & PG_SCAN_ADD_SUMS) != 0u ? sums[pc.block_offset + b] : 0u;
    run += offset;
    for (uint i = 0u; i < PG_SORT_ITEMS; ++i) {
        if (first + i < pc.n) result[first + i] = run;
        run += v[i];
    }
    if ((pc.flags & PG_SCAN_WRITE_TOTAL) != 0u && t == 0u) total_out[pc.total_index] = offset + total;
}

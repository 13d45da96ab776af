#version 450
// The whole sort of at most PG_SORT_SMALL items in one workgroup, every pass in shared memory:
// one dispatch instead of three per 4-bit digit (sort/radix_histogram, the scan,
// sort/radix_scatter). For CPU devices, where a dispatch's fixed cost outweighs a small
// sort's work (PTv3's coarser levels sort a few thousand codes many times a step).
//
// Each pass ranks the items stably as sort/radix_scatter.glsl does within a block
// (sort/radix_rank.glsl); the block is the whole input, so a rank is the item's place. Items past the count take the last digit and are
// never stored: they rank after every real item, and stay at the end pass after pass.
#extension GL_GOOGLE_include_directive : require
#include "sort/sort_config.h"
layout(local_size_x = PG_SORT_THREADS) in;
layout(std430, binding = 0) readonly buffer Params { uint params[]; };
layout(std430, binding = 1) buffer Keys { uint keys[]; };
layout(std430, binding = 2) buffer Values { uint values[]; };
layout(push_constant) uniform PushBlock { RadixBlockPush pc; };

#include "sort/radix_count.glsl"
#define ITEMS PG_SORT_SMALL_ITEMS
#define LAST_DIGIT (PG_SORT_RADIX - 1u)

// Between passes the items (low key words, high key words, values); while a pass counts, the
// counter table (PG_RADIX_ROWS x THREADS words) in the same memory: the items are in registers then.
shared uint s_mem[3 * PG_SORT_SMALL];
#include "sort/block_scan.glsl"
#define PG_RADIX_TABLE s_mem
#define PG_RADIX_RANK_ITEMS ITEMS
#include "sort/radix_rank.glsl"

void main() {
    const uint n = min(params[PG_SORT_PARAM_COUNT], uint(PG_SORT_SMALL));
    const uint t = gl_LocalInvocationIndex, first = t * ITEMS;
    const bool wide = pc.key_words == 2u;
    uint lo[ITEMS], hi[ITEMS], value[ITEMS], digit[ITEMS], rank[ITEMS];
    for (uint i = 0u; i < ITEMS; ++i) {
        const uint e = min(first + i, max(n, 1u) - 1u);
        lo[i] = keys[e * pc.key_words];
        hi[i] = wide ? keys[e * 2u + 1u] : 0u;
        value[i] = values[e];
    }
    const uint passes = (pc.key_bits + PG_SORT_DIGIT_BITS - 1u) / PG_SORT_DIGIT_BITS;
    for (uint pass = 0u; pass < passes; ++pass) {
        const uint shift = pass * PG_SORT_DIGIT_BITS;
        const uint mask = (1u << min(PG_SORT_DIGIT_BITS, pc.key_bits - shift)) - 1u;
        for (uint i = 0u; i < ITEMS; ++i) {
            const uint word = shift < 32u ? lo[i] >> shift : hi[i] >> (shift - 32u);
            digit[i] = first + i < n ? word & mask : LAST_DIGIT;
        }
        barrier();  // every invocation holds its items: the counter table may overwrite them
        pg_radix_block_ranks(digit, rank);
        barrier();  // the table is read: the items may overwrite it
        for (uint i = 0u; i < ITEMS; ++i) {
            if (first + i >= n) break;
            s_mem[rank[i]] = lo[i];
            s_mem[PG_SORT_SMALL + rank[i]] = hi[i];
            s_mem[2u * PG_SORT_SMALL + rank[i]] = value[i];
        }
        barrier();
        for (uint i = 0u; i < ITEMS; ++i) {
            const uint e = min(first + i, max(n, 1u) - 1u);
            lo[i] = s_mem[e];
            hi[i] = s_mem[PG_SORT_SMALL + e];
            value[i] = s_mem[2u * PG_SORT_SMALL + e];
        }
    }
    for (uint i = 0u; i < ITEMS; ++i) {
        const uint e = first + i;
        if (e >= n) break;
        keys[e * pc.key_words] = lo[i];
        if (wide) keys[e * 2u + 1u] = hi[i];
        values[e] = value[i];
    }
}

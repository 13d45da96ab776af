#version 450
// The whole sort of at most PG_SORT_SMALL items in one workgroup, every pass in shared memory:
// one dispatch instead of three per 4-bit digit (sort/radix_histogram, the scan,
// sort/radix_scatter). For CPU devices, where a dispatch's fixed cost outweighs a small
// sort's work (PTv3's coarser levels sort a few thousand codes many times a step).
//
// Each pass ranks the items stably as sort/radix_scatter.glsl does within a block (invocation t
// owns the run [t * ITEMS, (t + 1) * ITEMS), counts its digits in registers, and an exclusive
// scan of the (digit, invocation) counter table gives the ranks); the block is the whole
// input, so a rank is the item's place. Items past the count take the last digit and are
// never stored: they rank after every real item, and stay at the end pass after pass.
#extension GL_GOOGLE_include_directive : require
#include "sort/sort_config.h"
layout(local_size_x = PG_SORT_THREADS) in;
layout(std430, binding = 0) readonly buffer Params { uint params[]; };
layout(std430, binding = 1) buffer Keys { uint keys[]; };
layout(std430, binding = 2) buffer Values { uint values[]; };
layout(push_constant) uniform PushBlock { RadixBlockPush pc; };

#include "sort/radix_count.glsl"
#define ROWS PG_RADIX_ROWS
#define ITEMS PG_SORT_SMALL_ITEMS
#define LAST_DIGIT (PG_SORT_RADIX - 1u)

// Between passes the items (low key words, high key words, values); while a pass counts, the
// counter table (ROWS x THREADS words) in the same memory: the items are in registers then.
shared uint s_mem[3 * PG_SORT_SMALL];
#include "sort/block_scan.glsl"

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
        uint low = 0u, high = 0u;
        for (uint i = 0u; i < ITEMS; ++i) {
            const uint word = shift < 32u ? lo[i] >> shift : hi[i] >> (shift - 32u);
            digit[i] = first + i < n ? word & mask : LAST_DIGIT;
            rank[i] = pg_radix_count(digit[i], low, high);
        }
        barrier();  // every invocation holds its items: the table may overwrite them
        for (uint r = 0u; r < ROWS; ++r) s_mem[r * PG_SORT_THREADS + t] = pg_radix_counter_word(r, low, high);
        barrier();
        // Exclusive scan of the table in index order, both 16-bit halves at once (no carries:
        // fewer than 2^16 items).
        uint words[ROWS];
        uint sum = 0u;
        for (uint i = 0u; i < ROWS; ++i) {
            words[i] = s_mem[t * ROWS + i];
            sum += words[i];
        }
        uint total;
        uint run = pg_block_exclusive_scan(sum, total);
        for (uint i = 0u; i < ROWS; ++i) {
            s_mem[t * ROWS + i] = run;
            run += words[i];
        }
        barrier();
        const uint low_items = total & 0xFFFFu;  // the high half's digits come after these
        for (uint i = 0u; i < ITEMS; ++i) {
            const uint d = digit[i];
            const uint w = s_mem[(d % ROWS) * PG_SORT_THREADS + t];
            rank[i] += ((w >> (16u * (d / ROWS))) & 0xFFFFu) + (d >= ROWS ? low_items : 0u);
        }
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

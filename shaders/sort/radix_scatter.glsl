// Radix sort pass, step 2: ranks the keys of a block by digit, stably, and moves keys and
// values to the offsets of the scanned histogram table. Two variants include this body:
// sort/radix_scatter (PG_RADIX_EXCHANGE 1, for GPUs) and sort/radix_scatter_direct
// (PG_RADIX_EXCHANGE 0, for CPU devices).
//
// Stability without subgroup operations: sort/radix_rank.glsl (invocation t owns the run
// [t * ITEMS, (t + 1) * ITEMS) of its block; a scanned (digit, invocation) counter table
// gives each item its rank in the block).
//
// With PG_RADIX_EXCHANGE the ranked items pass through shared memory so that consecutive
// invocations write consecutive addresses (coalesced). Without it each invocation writes its
// items straight from registers: on lavapipe that is a third faster, and having the exchange
// code in the same shader, even behind a uniform branch, costs as much again.
#include "common/dispatch.glsl"
#include "sort/sort_config.h"
layout(local_size_x = PG_SORT_THREADS) in;
layout(std430, binding = 0) readonly buffer Params { uint params[]; };
layout(std430, binding = 1) readonly buffer SrcKeys { uint src_keys[]; };
layout(std430, binding = 2) readonly buffer SrcValues { uint src_values[]; };
layout(std430, binding = 3) readonly buffer Offsets { uint offsets[]; };
layout(std430, binding = 4) writeonly buffer DstKeys { uint dst_keys[]; };
layout(std430, binding = 5) writeonly buffer DstValues { uint dst_values[]; };
layout(push_constant) uniform PushBlock { RadixPush pc; };

#include "sort/radix_count.glsl"
#define ROWS PG_RADIX_ROWS
#define LAST_DIGIT (PG_SORT_RADIX - 1u)

#if PG_RADIX_EXCHANGE
// First the counter table (ROWS x THREADS words), then the exchange buffer: one array.
shared uint s_buffer[max(PG_SORT_BLOCK, ROWS * PG_SORT_THREADS)];
#else
shared uint s_buffer[ROWS * PG_SORT_THREADS];
#endif
// Per digit: global offset of the digit's first item in this block, minus its block rank.
shared uint s_base[PG_SORT_RADIX];
#include "sort/block_scan.glsl"
#define PG_RADIX_TABLE s_buffer
#define PG_RADIX_RANK_ITEMS PG_SORT_ITEMS
#include "sort/radix_rank.glsl"

void main() {
    uint n = params[PG_SORT_PARAM_COUNT];
    uint b = pg_group_index();
    uint begin = b * PG_SORT_BLOCK;
    if (begin >= n) return;
    uint t = gl_LocalInvocationIndex;
    uint word = pc.shift >> 5u, shift = pc.shift & 31u;
    bool wide = pc.key_words == 2u;

    // Load this invocation's run. Items past the count get the last digit, so they rank after
    // every real item of the block and are never written.
    uint first = begin + t * PG_SORT_ITEMS;
    uint key_digit_word[PG_SORT_ITEMS], key_other_word[PG_SORT_ITEMS], value[PG_SORT_ITEMS];
    uint digit[PG_SORT_ITEMS], rank[PG_SORT_ITEMS];
    for (uint i = 0u; i < PG_SORT_ITEMS; ++i) {
        uint e = first + i;
        key_digit_word[i] = 0u;
        key_other_word[i] = 0u;
        value[i] = 0u;
        digit[i] = LAST_DIGIT;
        if (e < n) {
            key_digit_word[i] = src_keys[e * pc.key_words + word];
            if (wide) key_other_word[i] = src_keys[e * 2u + (word ^ 1u)];
            value[i] = src_values[e];
            digit[i] = (key_digit_word[i] >> shift) & pc.mask;
        }
    }

    uint low_items = pg_radix_block_ranks(digit, rank);
    // Each digit's global offset less its block rank, from the scanned table (the high half's
    // digits come after every item of the low ones).
    if (t < PG_SORT_RADIX) {
        uint w = s_buffer[(t % ROWS) * PG_SORT_THREADS];
        uint start = t < ROWS ? (w & 0xFFFFu) : (w >> 16u) + low_items;
        s_base[t] = offsets[t * pc.stride + b] - start;
    }
    barrier();

#if PG_RADIX_EXCHANGE
    uint valid = min(n - begin, uint(PG_SORT_BLOCK));
    // Exchange the word holding the digit first: its digit gives each ranked item's target.
    for (uint i = 0u; i < PG_SORT_ITEMS; ++i) s_buffer[rank[i]] = key_digit_word[i];
    barrier();
    uint target[PG_SORT_ITEMS];
    for (uint i = 0u; i < PG_SORT_ITEMS; ++i) {
        uint j = i * PG_SORT_THREADS + t;
        target[i] = 0u;
        if (j < valid) {
            uint k = s_buffer[j];
            target[i] = s_base[(k >> shift) & pc.mask] + j;
            dst_keys[target[i] * pc.key_words + word] = k;
        }
    }
    if (wide) {
        barrier();
        for (uint i = 0u; i < PG_SORT_ITEMS; ++i) s_buffer[rank[i]] = key_other_word[i];
        barrier();
        for (uint i = 0u; i < PG_SORT_ITEMS; ++i) {
            uint j = i * PG_SORT_THREADS + t;
            if (j < valid) dst_keys[target[i] * 2u + (word ^ 1u)] = s_buffer[j];
        }
    }
    barrier();
    for (uint i = 0u; i < PG_SORT_ITEMS; ++i) s_buffer[rank[i]] = value[i];
    barrier();
    for (uint i = 0u; i < PG_SORT_ITEMS; ++i) {
        uint j = i * PG_SORT_THREADS + t;
        if (j < valid) dst_values[target[i]] = s_buffer[j];
    }
#else
    for (uint i = 0u; i < PG_SORT_ITEMS; ++i) {
        if (first + i >= n) break;
        uint target = s_base[digit[i]] + rank[i];
        dst_keys[target * pc.key_words + word] = key_digit_word[i];
        if (wide) dst_keys[target * 2u + (word ^ 1u)] = key_other_word[i];
        dst_values[target] = value[i];
    }
#endif
}

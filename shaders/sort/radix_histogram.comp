#version 450
// Radix sort pass, step 1: how many keys of each block have each digit. Writes the
// digit-major table hist[digit * stride + block] that one exclusive scan turns into offsets.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "sort/sort_config.h"
layout(local_size_x = PG_SORT_THREADS) in;
layout(std430, binding = 0) readonly buffer Params { uint params[]; };
layout(std430, binding = 1) readonly buffer Keys { uint keys[]; };
layout(std430, binding = 2) writeonly buffer Hist { uint hist[]; };
layout(push_constant) uniform PushBlock { RadixPush pc; };

#include "sort/radix_count.glsl"
#define ROWS PG_RADIX_ROWS
#define THREADS_PER_ROW (PG_SORT_THREADS / ROWS)
#define COLUMNS_PER_THREAD (PG_SORT_THREADS / THREADS_PER_ROW)

// counters[row * THREADS + t]: invocation t's count of digit row (low half) and row + ROWS
// (high half), counted in registers first: no atomics.
shared uint s_counters[ROWS * PG_SORT_THREADS];
shared uint s_partial[PG_SORT_THREADS];

void main() {
    uint n = params[PG_SORT_PARAM_COUNT];
    uint b = pg_group_index();
    uint begin = b * PG_SORT_BLOCK;
    if (begin >= n) return;
    uint t = gl_LocalInvocationIndex;
    uint word = pc.shift >> 5u, shift = pc.shift & 31u;

    uint low = 0u, high = 0u;
    for (uint i = 0u; i < PG_SORT_ITEMS; ++i) {
        uint e = begin + i * PG_SORT_THREADS + t;
        if (e < n) pg_radix_count((keys[e * pc.key_words + word] >> shift) & pc.mask, low, high);
    }
    for (uint r = 0u; r < ROWS; ++r) s_counters[r * PG_SORT_THREADS + t] = pg_radix_counter_word(r, low, high);
    barrier();
    // Sum each row: THREADS_PER_ROW invocations add COLUMNS_PER_THREAD columns each, then one
    // invocation per row adds those. A half never exceeds PG_SORT_BLOCK < 2^16: no carries.
    uint row = t / THREADS_PER_ROW, column = (t % THREADS_PER_ROW) * COLUMNS_PER_THREAD;
    uint sum = 0u;
    for (uint c = 0u; c < COLUMNS_PER_THREAD; ++c) sum += s_counters[row * PG_SORT_THREADS + column + c];
    s_partial[t] = sum;
    barrier();
    if (t < ROWS) {
        uint total = 0u;
        for (uint c = 0u; c < THREADS_PER_ROW; ++c) total += s_partial[t * THREADS_PER_ROW + c];
        hist[t * pc.stride + b] = total & 0xFFFFu;
        hist[(t + ROWS) * pc.stride + b] = total >> 16u;
    }
}

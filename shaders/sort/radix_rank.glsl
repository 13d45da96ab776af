// A block's stable ranks by digit, shared by sort/radix_scatter.glsl (one pass of a block) and
// sort/radix_sort_block (every pass of a whole small sort). Invocation t owns the run
// [t * PG_RADIX_RANK_ITEMS, (t + 1) * PG_RADIX_RANK_ITEMS) of the block, counts its digits in
// registers and stores the counts in its column of the (digit, invocation) counter table in
// PG_RADIX_TABLE (a shared uint array of at least PG_RADIX_ROWS x PG_SORT_THREADS words). An
// exclusive scan of the table in index order gives, for every (digit, t), the number of items
// of the block that come before t's first item of that digit in sorted order; adding t's
// running count gives each item its rank in the block.
//
// The includer defines PG_RADIX_TABLE and PG_RADIX_RANK_ITEMS and includes sort/radix_count.glsl
// and sort/block_scan.glsl first.
#ifndef PG_SORT_RADIX_RANK_GLSL
#define PG_SORT_RADIX_RANK_GLSL

// Fills rank[] and returns how many items of the block have a digit below PG_RADIX_ROWS (the
// high half of the table comes after them). The scanned table stays in PG_RADIX_TABLE until the
// caller's next barrier.
uint pg_radix_block_ranks(uint digit[PG_RADIX_RANK_ITEMS], out uint rank[PG_RADIX_RANK_ITEMS]) {
    const uint t = gl_LocalInvocationIndex;
    uint low = 0u, high = 0u;
    for (uint i = 0u; i < PG_RADIX_RANK_ITEMS; ++i) rank[i] = pg_radix_count(digit[i], low, high);
    for (uint r = 0u; r < PG_RADIX_ROWS; ++r)
        PG_RADIX_TABLE[r * PG_SORT_THREADS + t] = pg_radix_counter_word(r, low, high);
    barrier();
    // Invocation t scans words [t * ROWS, (t + 1) * ROWS). Both 16-bit halves scan at once:
    // the low half never carries, as a block holds fewer than 2^16 items.
    uint words[PG_RADIX_ROWS];
    uint sum = 0u;
    for (uint i = 0u; i < PG_RADIX_ROWS; ++i) {
        words[i] = PG_RADIX_TABLE[t * PG_RADIX_ROWS + i];
        sum += words[i];
    }
    uint total;
    uint run = pg_block_exclusive_scan(sum, total);
    for (uint i = 0u; i < PG_RADIX_ROWS; ++i) {
        PG_RADIX_TABLE[t * PG_RADIX_ROWS + i] = run;
        run += words[i];
    }
    barrier();
    const uint low_items = total & 0xFFFFu;
    for (uint i = 0u; i < PG_RADIX_RANK_ITEMS; ++i) {
        const uint d = digit[i];
        const uint w = PG_RADIX_TABLE[(d % PG_RADIX_ROWS) * PG_SORT_THREADS + t];
        rank[i] += ((w >> (16u * (d / PG_RADIX_ROWS))) & 0xFFFFu) + (d >= PG_RADIX_ROWS ? low_items : 0u);
    }
    return low_items;
}
#endif

// Radix sort: per-invocation digit counts kept in registers, 4 bits per digit (an invocation
// has PG_SORT_ITEMS < 16 items): `low` holds digits 0..7, `high` digits 8..15.
#ifndef PG_SORT_RADIX_COUNT_GLSL
#define PG_SORT_RADIX_COUNT_GLSL
#include "sort/sort_config.h"

#define PG_RADIX_ROWS (PG_SORT_RADIX / 2)

// Counts `digit` and returns how many of this invocation's items had it before.
uint pg_radix_count(uint digit, inout uint low, inout uint high) {
    uint shift = 4u * (digit % PG_RADIX_ROWS);
    bool is_low = digit < PG_RADIX_ROWS;
    uint before = ((is_low ? low : high) >> shift) & 0xFu;
    low += is_low ? 1u << shift : 0u;
    high += is_low ? 0u : 1u << shift;
    return before;
}

// Word `row` of an invocation's column in the counter table: the count of digit `row` in the
// low 16 bits, of digit `row + 8` in the high 16 bits.
uint pg_radix_counter_word(uint row, uint low, uint high) {
    return ((low >> (4u * row)) & 0xFu) | (((high >> (4u * row)) & 0xFu) << 16u);
}
#endif

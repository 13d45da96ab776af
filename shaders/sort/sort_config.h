// Tunables and push-constant layouts shared by engine/sort (C++) and shaders/sort (GLSL):
// one definition, no drift between host and shaders.
#ifndef PG_SORT_CONFIG_H
#define PG_SORT_CONFIG_H

#ifdef __cplusplus
#include <cstdint>
namespace pg::sort::gpu {
using uint = uint32_t;
#endif

#define PG_SORT_THREADS 256
// Items per invocation; a block of PG_SORT_BLOCK items is one workgroup's share. 12 rather
// than 8: fewer workgroups and barriers per item, which lavapipe feels most.
#define PG_SORT_ITEMS 12
#define PG_SORT_BLOCK (PG_SORT_THREADS * PG_SORT_ITEMS)
// Radix digits: 4 bits, 16 buckets. A block's counts per (digit, invocation) are stored as two
// 16-bit halves of PG_SORT_RADIX / 2 words per invocation (a block holds < 2^16 items), and
// an invocation counts its own items in 4-bit fields, so PG_SORT_ITEMS must stay below 16.
#define PG_SORT_DIGIT_BITS 4
#define PG_SORT_RADIX 16
// sort/radix_sort_block: a whole sort in one workgroup's shared memory (32 KiB on lavapipe:
// three words per item, then the block scan's table), for at most PG_SORT_SMALL items.
#define PG_SORT_SMALL_ITEMS 10
#define PG_SORT_SMALL (PG_SORT_THREADS * PG_SORT_SMALL_ITEMS)
// Layout of the sorter's parameter buffer: indirect dispatch arguments, then the item count.
#define PG_SORT_PARAM_ARGS 0
#define PG_SORT_PARAM_COUNT 3
#define PG_SORT_PARAM_WORDS 4
// PrefixPush.flags
#define PG_SCAN_ADD_SUMS 1
#define PG_SCAN_WRITE_TOTAL 2

// One radix pass (sort/radix_histogram, sort/radix_scatter).
struct RadixPush {
    uint shift;      // lowest key bit of this pass's digit
    uint mask;       // (1 << digit bits) - 1; the last pass may use fewer than 4 bits
    uint stride;     // blocks of the capacity: the histogram table is digit-major, RADIX x stride
    uint key_words;  // 1 for 32-bit keys, 2 for 64-bit keys (low word first)
};

// sort/radix_sort_block: every pass over the low key_bits bits.
struct RadixBlockPush {
    uint key_bits;
    uint key_words;  // 1 or 2
    uint pad0, pad1;
};

// sort/radix_setup: GPU count -> clamped count and indirect arguments.
struct RadixSetupPush {
    uint count_index;  // uint index of the count in the bound window
    uint capacity;     // counts are clamped to this
    uint limit;        // the device's group-count limit along x
    uint pad;
};

// sort/radix_copy: the result back from the scratch buffers.
struct RadixCopyPush {
    uint key_words;
    uint pad0, pad1, pad2;
};

// sort/prefix_reduce, sort/prefix_scan: one window of at most one storage-buffer range.
struct PrefixPush {
    uint n;             // items in the window
    uint block_offset;  // index of the window's first block among all blocks (block sums)
    uint flags;         // PG_SCAN_ADD_SUMS | PG_SCAN_WRITE_TOTAL
    uint total_index;   // uint index of the total in the bound window
};

#ifdef __cplusplus
}  // namespace pg::sort::gpu
#endif

#endif

#pragma once
// Stable key-value radix sort on the GPU: 32-bit keys or 64-bit keys (stored as two uints,
// low word first), uint32 values, sorting only the low `key_bits` bits.
//
// LSD, 4-bit digits, ceil(key_bits / 4) passes ping-ponging with scratch buffers (copied
// back after an odd count). A pass: sort/radix_histogram counts digits per block of 3072
// items into a digit-major table, PrefixSum scans it, sort/radix_scatter ranks each block
// stably in shared memory and writes items to their place (sort/radix_scatter_direct on CPU
// devices). Exact and deterministic on any device and subgroup size (no subgroup operations,
// no atomics). On CPU devices up to PG_SORT_SMALL items sort in one dispatch, every pass in one
// workgroup's shared memory (sort/radix_sort_block). The count lives on the GPU (indirect dispatch), so sort() and sort_indirect()
// share every kernel. Bits above key_bits are ignored for order and kept. The keys of the
// capacity must fit one storage binding (lavapipe: 128 MiB, 16M 64-bit keys).
#include <cstdint>
#include <string>
#include <vector>

#include "engine/sort/prefix_sum.h"
#include "engine/vk/buffer.h"
#include "engine/vk/commands.h"

namespace pg::sort {

enum class KeyWidth { Bits32, Bits64 };

class RadixSort {
public:
    explicit RadixSort(vk::Context& ctx);

    // Sorts keys[0..count) with their values; the result is in `keys` and `values`.
    void sort(vk::CommandList& cmd, vk::Buffer& keys, vk::Buffer& values, uint32_t count, uint32_t key_bits,
              KeyWidth width);
    // Same with the count read on the GPU from a uint at `count_offset` bytes of `count_buffer`
    // (clamped to `capacity`, which sizes the scratch buffers): no host round trip.
    void sort_indirect(vk::CommandList& cmd, vk::Buffer& keys, vk::Buffer& values, const vk::Buffer& count_buffer,
                       VkDeviceSize count_offset, uint32_t capacity, uint32_t key_bits, KeyWidth width);

private:
    void prepare(uint32_t capacity, KeyWidth width);
    // The passes, once params_ holds the count and the indirect arguments.
    void record(vk::CommandList& cmd, vk::Buffer& keys, vk::Buffer& values, uint32_t capacity, uint32_t key_bits,
                KeyWidth width);
    void grow(vk::Buffer& buffer, VkDeviceSize bytes, const char* name);

    vk::Context& ctx_;
    PrefixSum scan_;
    std::string scatter_shader_;  // sort/radix_scatter (GPUs) or sort/radix_scatter_direct (CPUs)
    bool small_ = false;          // sorts of at most PG_SORT_SMALL items in one dispatch (CPUs)
    // Scratch, grown on demand and reused: ping-pong keys/values, the digit-major histogram
    // table (16 x blocks of the capacity) and its scan, and the parameter buffer (indirect
    // arguments + count).
    vk::Buffer keys_tmp_, values_tmp_, histogram_, offsets_, params_;
    // Buffers replaced by bigger ones, kept alive: a command list recorded earlier may use them.
    std::vector<vk::Buffer> retired_;
};

}  // namespace pg::sort

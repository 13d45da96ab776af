#pragma once
// Exclusive prefix sum of uint32 on the GPU: reduce-then-scan over blocks of 3072 values,
// recursing on the block sums, so any n works; inputs larger than one storage-buffer range
// (128 MiB on lavapipe) are processed in windows. Sums wrap modulo 2^32.
#include <cstdint>
#include <deque>
#include <vector>

#include "engine/vk/buffer.h"
#include "engine/vk/commands.h"

namespace pg::sort {

class PrefixSum {
public:
    explicit PrefixSum(vk::Context& ctx);
    // out[i] = in[0] + ... + in[i-1] for i < n (in == out allowed). If `total` is given, the sum
    // of all n values is written as a uint at `total_offset` bytes of it.
    void exclusive(vk::CommandList& cmd, const vk::Buffer& in, const vk::Buffer& out, uint32_t n,
                   const vk::Buffer* total = nullptr, VkDeviceSize total_offset = 0);

private:
    // Reduce-then-scan: block sums of `in` go to the level's buffer, which is scanned by the
    // next level, then each block is scanned with its offset. Inputs larger than one storage
    // binding are processed in windows.
    void scan_level(vk::CommandList& cmd, const vk::Buffer& in, const vk::Buffer& out, uint32_t n, size_t level,
                    const vk::Buffer* total, VkDeviceSize total_offset);
    vk::Buffer& level_sums(size_t level, VkDeviceSize bytes);

    vk::Context& ctx_;
    std::deque<vk::Buffer> levels_;  // block sums per level (a deque: references stay valid)
    // Buffers replaced by bigger ones, kept alive: a command list recorded earlier may use them.
    std::vector<vk::Buffer> retired_;
};

}  // namespace pg::sort

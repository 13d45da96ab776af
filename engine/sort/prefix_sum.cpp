#include "engine/sort/prefix_sum.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "engine/vk/context.h"
#include "shaders/sort/sort_config.h"

namespace pg::sort {

namespace {

constexpr uint32_t kBlock = PG_SORT_BLOCK;
// The largest minStorageBufferOffsetAlignment Vulkan allows: windows start on it.
constexpr VkDeviceSize kBindAlign = 256;

uint32_t blocks(uint64_t n) { return vk::ceil_div(n, kBlock); }

vk::BufferRange words(const vk::Buffer& b, uint64_t first, uint64_t count) {
    return vk::BufferRange(b, first * 4, std::max<uint64_t>(count, 1) * 4);
}

}  // namespace

PrefixSum::PrefixSum(vk::Context& ctx) : ctx_(ctx) {}

void PrefixSum::exclusive(vk::CommandList& cmd, const vk::Buffer& in, const vk::Buffer& out, uint32_t n,
                          const vk::Buffer* total, VkDeviceSize total_offset) {
    const VkDeviceSize bytes = VkDeviceSize(n) * 4;
    if (bytes > in.size() || bytes > out.size())
        throw std::invalid_argument("PrefixSum: " + std::to_string(n) + " values do not fit in buffer '" +
                                    (bytes > in.size() ? in.name() : out.name()) + "'");
    if (total && (total_offset % 4 != 0 || total_offset + 4 > total->size()))
        throw std::invalid_argument("PrefixSum: total offset " + std::to_string(total_offset) +
                                    " is unaligned or past the end of buffer '" + total->name() + "'");
    if (n == 0) {
        if (total) {
            const uint32_t zero = 0;
            cmd.update(*total, &zero, 4, total_offset);
        }
        return;
    }
    scan_level(cmd, in, out, n, 0, total, total_offset);
}

void PrefixSum::scan_level(vk::CommandList& cmd, const vk::Buffer& in, const vk::Buffer& out, uint32_t n,
                           size_t level, const vk::Buffer* total, VkDeviceSize total_offset) {
    if (n <= kBlock) {
        gpu::PrefixPush push{n, 0, 0, 0};
        vk::BufferRange total_range = words(out, 0, n);  // bound but unused without a total
        if (total) {
            const VkDeviceSize at = total_offset & ~(kBindAlign - 1);
            total_range = vk::BufferRange(*total, at, total_offset + 4 - at);
            push.flags = PG_SCAN_WRITE_TOTAL;
            push.total_index = uint32_t((total_offset - at) / 4);
        }
        cmd.dispatch("sort/prefix_scan", {words(in, 0, n), words(out, 0, n), words(in, 0, n), total_range}, push, 1);
        return;
    }
    // Windows of whole blocks that fit one storage binding (lavapipe: 128 MiB).
    const uint64_t range_words = std::min<uint64_t>(ctx_.info().max_storage_buffer_range / 4, uint64_t(1) << 30);
    const uint64_t window = std::max<uint64_t>(range_words / kBlock, 1) * kBlock;
    const uint32_t sum_count = blocks(n);
    vk::Buffer& sums = level_sums(level, VkDeviceSize(sum_count) * 4);
    for (uint64_t first = 0; first < n; first += window) {
        const uint32_t len = uint32_t(std::min<uint64_t>(window, n - first));
        cmd.dispatch("sort/prefix_reduce", {words(in, first, len), words(sums, 0, sum_count)},
                     gpu::PrefixPush{len, uint32_t(first / kBlock), 0, 0}, blocks(len));
    }
    scan_level(cmd, sums, sums, sum_count, level + 1, total, total_offset);
    for (uint64_t first = 0; first < n; first += window) {
        const uint32_t len = uint32_t(std::min<uint64_t>(window, n - first));
        cmd.dispatch("sort/prefix_scan",
                     {words(in, first, len), words(out, first, len), words(sums, 0, sum_count), words(out, first, len)},
                     gpu::PrefixPush{len, uint32_t(first / kBlock), PG_SCAN_ADD_SUMS, 0}, blocks(len));
    }
}

vk::Buffer& PrefixSum::level_sums(size_t level, VkDeviceSize bytes) {
    while (levels_.size() <= level) levels_.emplace_back();
    vk::Buffer& b = levels_[level];
    if (b.valid() && b.size() >= bytes) return b;
    if (b.valid()) retired_.push_back(std::move(b));
    b = vk::Buffer(ctx_, bytes, vk::MemoryUse::Device, "prefix sum level " + std::to_string(level));
    return b;
}

}  // namespace pg::sort

#include "engine/sort/radix_sort.h"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "engine/vk/context.h"
#include "shaders/sort/sort_config.h"

namespace pg::sort {

namespace {

constexpr uint32_t kBlock = PG_SORT_BLOCK;
constexpr uint32_t kRadix = PG_SORT_RADIX;
constexpr uint32_t kDigitBits = PG_SORT_DIGIT_BITS;
constexpr VkDeviceSize kBindAlign = 256;  // the largest minStorageBufferOffsetAlignment allowed

uint32_t blocks(uint32_t n) { return vk::ceil_div(n, kBlock); }
uint32_t key_words(KeyWidth w) { return w == KeyWidth::Bits64 ? 2 : 1; }

void check_arguments(const vk::Buffer& keys, const vk::Buffer& values, uint32_t items, uint32_t key_bits,
                     KeyWidth width) {
    if (key_bits > 32 * key_words(width))
        throw std::invalid_argument("RadixSort: key_bits " + std::to_string(key_bits) + " exceeds the " +
                                    std::to_string(32 * key_words(width)) + "-bit key width");
    const VkDeviceSize key_bytes = VkDeviceSize(items) * 4 * key_words(width);
    if (key_bytes > keys.size())
        throw std::invalid_argument("RadixSort: keys buffer '" + keys.name() + "' holds " +
                                    std::to_string(keys.size()) + " bytes, " + std::to_string(items) + " keys need " +
                                    std::to_string(key_bytes));
    if (VkDeviceSize(items) * 4 > values.size())
        throw std::invalid_argument("RadixSort: values buffer '" + values.name() + "' holds " +
                                    std::to_string(values.size()) + " bytes, " + std::to_string(items) +
                                    " values need " + std::to_string(VkDeviceSize(items) * 4));
}

}  // namespace

RadixSort::RadixSort(vk::Context& ctx) : ctx_(ctx), scan_(ctx) {
    // GPUs want coalesced writes (an exchange through shared memory); CPU devices are faster
    // writing from registers. PG_SORT_SCATTER=exchange|direct overrides, for tests and benches.
    bool direct = ctx.info().type == VK_PHYSICAL_DEVICE_TYPE_CPU;
    if (const char* mode = std::getenv("PG_SORT_SCATTER")) {
        const std::string m = mode;
        if (m != "exchange" && m != "direct")
            throw std::invalid_argument("PG_SORT_SCATTER is '" + m + "': expected 'exchange' or 'direct'");
        direct = m == "direct";
    }
    scatter_shader_ = direct ? "sort/radix_scatter_direct" : "sort/radix_scatter";
    // The same devices sort up to PG_SORT_SMALL items in one dispatch (sort/radix_sort_block).
    small_ = direct;
}

void RadixSort::sort(vk::CommandList& cmd, vk::Buffer& keys, vk::Buffer& values, uint32_t count, uint32_t key_bits,
                     KeyWidth width) {
    check_arguments(keys, values, count, key_bits, width);
    if (count <= 1 || key_bits == 0) return;
    prepare(count, width);
    // The host knows the count: write what sort/radix_setup would compute.
    const uint32_t groups = blocks(count), limit = ctx_.max_group_count_x();
    const uint32_t params[PG_SORT_PARAM_WORDS] = {groups <= limit ? groups : limit,
                                                  groups <= limit ? 1 : vk::ceil_div(groups, limit), 1, count};
    cmd.update(params_, params, sizeof params);
    record(cmd, keys, values, count, key_bits, width);
}

void RadixSort::sort_indirect(vk::CommandList& cmd, vk::Buffer& keys, vk::Buffer& values,
                              const vk::Buffer& count_buffer, VkDeviceSize count_offset, uint32_t capacity,
                              uint32_t key_bits, KeyWidth width) {
    check_arguments(keys, values, capacity, key_bits, width);
    if (count_offset % 4 != 0 || count_offset + 4 > count_buffer.size())
        throw std::invalid_argument("RadixSort: count offset " + std::to_string(count_offset) +
                                    " is unaligned or past the end of buffer '" + count_buffer.name() + "'");
    if (capacity <= 1 || key_bits == 0) return;  // at most one item: already sorted
    prepare(capacity, width);
    const VkDeviceSize at = count_offset & ~(kBindAlign - 1);
    cmd.dispatch("sort/radix_setup", {vk::BufferRange(count_buffer, at, count_offset + 4 - at), params_},
                 gpu::RadixSetupPush{uint32_t((count_offset - at) / 4), capacity, ctx_.max_group_count_x(), 0}, 1);
    record(cmd, keys, values, capacity, key_bits, width);
}

void RadixSort::prepare(uint32_t capacity, KeyWidth width) {
    const VkDeviceSize items = capacity, table = VkDeviceSize(kRadix) * blocks(capacity);
    grow(keys_tmp_, items * 4 * key_words(width), "radix sort keys");
    grow(values_tmp_, items * 4, "radix sort values");
    grow(histogram_, table * 4, "radix sort histogram");
    grow(offsets_, table * 4, "radix sort offsets");
    grow(params_, PG_SORT_PARAM_WORDS * 4, "radix sort params");
}

void RadixSort::grow(vk::Buffer& buffer, VkDeviceSize bytes, const char* name) {
    if (buffer.valid() && buffer.size() >= bytes) return;
    VkDeviceSize size = bytes;
    if (buffer.valid()) {
        // Grow by half at least, so a slowly rising count does not reallocate every call.
        size = std::max(bytes, buffer.size() + buffer.size() / 2);
        if (size > ctx_.info().max_buffer_size || size > ctx_.info().max_allocation_size) size = bytes;
        retired_.push_back(std::move(buffer));
    }
    buffer = vk::Buffer(ctx_, size, vk::MemoryUse::Device, name);
}

void RadixSort::record(vk::CommandList& cmd, vk::Buffer& keys, vk::Buffer& values, uint32_t capacity,
                       uint32_t key_bits, KeyWidth width) {
    const uint32_t words = key_words(width);
    if (small_ && capacity <= PG_SORT_SMALL) {
        const VkDeviceSize key_bytes = VkDeviceSize(capacity) * 4 * words, value_bytes = VkDeviceSize(capacity) * 4;
        cmd.dispatch("sort/radix_sort_block", {params_, vk::BufferRange(keys, 0, key_bytes), vk::BufferRange(values, 0, value_bytes)},
                     gpu::RadixBlockPush{key_bits, words, 0, 0}, 1);
        return;
    }
    const uint32_t stride = blocks(capacity);
    const uint32_t table = kRadix * stride;
    const VkDeviceSize key_bytes = VkDeviceSize(capacity) * 4 * words, value_bytes = VkDeviceSize(capacity) * 4;
    const vk::BufferRange user_keys(keys, 0, key_bytes), user_values(values, 0, value_bytes);
    const vk::BufferRange tmp_keys(keys_tmp_, 0, key_bytes), tmp_values(values_tmp_, 0, value_bytes);
    const vk::BufferRange hist(histogram_, 0, VkDeviceSize(table) * 4), offs(offsets_, 0, VkDeviceSize(table) * 4);

    // Blocks past the GPU count never write their histogram entries: they must read as zero.
    cmd.fill(histogram_, 0, 0, VkDeviceSize(table) * 4);
    const uint32_t passes = vk::ceil_div(key_bits, kDigitBits);
    for (uint32_t pass = 0; pass < passes; ++pass) {
        const bool from_user = pass % 2 == 0;
        const vk::BufferRange& src_keys = from_user ? user_keys : tmp_keys;
        const vk::BufferRange& src_values = from_user ? user_values : tmp_values;
        const vk::BufferRange& dst_keys = from_user ? tmp_keys : user_keys;
        const vk::BufferRange& dst_values = from_user ? tmp_values : user_values;
        const uint32_t shift = pass * kDigitBits, bits = std::min(kDigitBits, key_bits - shift);
        const gpu::RadixPush push{shift, (1u << bits) - 1, stride, words};
        cmd.dispatch_indirect("sort/radix_histogram", {params_, src_keys, hist}, push, params_);
        scan_.exclusive(cmd, histogram_, offsets_, table);
        cmd.dispatch_indirect(scatter_shader_, {params_, src_keys, src_values, offs, dst_keys, dst_values}, push,
                              params_);
    }
    if (passes % 2 == 1)
        cmd.dispatch_indirect("sort/radix_copy", {params_, tmp_keys, tmp_values, user_keys, user_values},
                              gpu::RadixCopyPush{words, 0, 0, 0}, params_);
}

}  // namespace pg::sort

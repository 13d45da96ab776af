#include "engine/vk/commands.h"

#include <algorithm>
#include <cstring>
#include <mutex>
#include <stdexcept>

#include "engine/vk/check.h"
#include "engine/vk/context.h"
#include "engine/vk/pipeline.h"

namespace pg::vk {

CommandList::CommandList(Context& ctx) : ctx_(ctx) {
    VkDevice dev = ctx.device();
    VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pci.queueFamilyIndex = ctx.queue_family();
    PG_VK(vkCreateCommandPool(dev, &pci, nullptr, &pool_));
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = pool_;
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    PG_VK(vkAllocateCommandBuffers(dev, &ai, &cmd_));
    VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    PG_VK(vkCreateFence(dev, &fci, nullptr, &fence_));
    if (ctx.info().timestamps) {
        VkQueryPoolCreateInfo qci{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
        qci.queryType = VK_QUERY_TYPE_TIMESTAMP;
        qci.queryCount = kMaxQueries;
        PG_VK(vkCreateQueryPool(dev, &qci, nullptr, &queries_));
    }
}

CommandList::~CommandList() {
    VkDevice dev = ctx_.device();
    if (recording_) vkEndCommandBuffer(cmd_);
    if (queries_) vkDestroyQueryPool(dev, queries_, nullptr);
    vkDestroyFence(dev, fence_, nullptr);
    vkDestroyCommandPool(dev, pool_, nullptr);
}

void CommandList::begin_if_needed() {
    if (recording_) return;
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    PG_VK(vkBeginCommandBuffer(cmd_, &bi));
    if (queries_) vkCmdResetQueryPool(cmd_, queries_, 0, kMaxQueries);
    recording_ = true;
    touched_.clear();
    pass_names_.clear();
    pass_open_ = false;
    std::fill(staging_used_.begin(), staging_used_.end(), VkDeviceSize(0));  // the last submission is done
}

void CommandList::upload(const Buffer& dst, const void* data, VkDeviceSize bytes, VkDeviceSize offset) {
    if (offset + bytes > dst.size()) throw std::out_of_range("upload past the end of buffer '" + dst.name() + "'");
    if (bytes == 0) return;
    if (dst.mapped()) {
        std::memcpy(static_cast<char*>(dst.data()) + offset, data, bytes);
        return;
    }
    begin_if_needed();
    size_t c = 0;
    while (c < staging_.size() && staging_[c].size() - staging_used_[c] < bytes) ++c;
    if (c == staging_.size()) {
        // None holds it: if this recording uses none yet, one chunk of this size replaces them all
        // (memory stays what one submission needs, not the sum of every size seen).
        if (std::all_of(staging_used_.begin(), staging_used_.end(), [](VkDeviceSize u) { return u == 0; })) {
            staging_.clear();
            staging_used_.clear();
            c = 0;
        }
        staging_.emplace_back(ctx_, std::max<VkDeviceSize>(bytes, VkDeviceSize(1) << 20), MemoryUse::Upload, "upload staging");
        staging_used_.push_back(0);
    }
    const VkDeviceSize at = staging_used_[c];
    std::memcpy(static_cast<char*>(staging_[c].data()) + at, data, bytes);
    copy(staging_[c], dst, bytes, at, offset);
    staging_used_[c] = at + ((bytes + 15) & ~VkDeviceSize(15));
}

void CommandList::barrier() {
    begin_if_needed();
    // One global barrier covers every hazard between compute, transfer and indirect reads;
    // per-buffer barriers buy nothing on the drivers we target.
    VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_SHADER_READ_BIT |
                       VK_ACCESS_TRANSFER_READ_BIT;
    mb.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT |
                       VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_INDIRECT_COMMAND_READ_BIT;
    vkCmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT |
                             VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT,
                         0, 1, &mb, 0, nullptr, 0, nullptr);
    touched_.clear();
}

void CommandList::touch(const Buffer& b) {
    if (!b.valid()) throw std::logic_error("command uses an unallocated buffer '" + b.name() + "'");
    if (std::find(touched_.begin(), touched_.end(), b.handle()) != touched_.end()) barrier();
    touched_.push_back(b.handle());
}

ComputePipeline& CommandList::bind(const std::string& shader, std::span<const BufferRange> buffers,
                                   const void* push, uint32_t push_bytes) {
    begin_if_needed();
    // Hazards are judged on the whole set of this command's buffers before any is recorded.
    for (auto& r : buffers)
        if (std::find(touched_.begin(), touched_.end(), r.buffer->handle()) != touched_.end()) {
            barrier();
            break;
        }
    for (auto& r : buffers)
        if (std::find(touched_.begin(), touched_.end(), r.buffer->handle()) == touched_.end()) touch(*r.buffer);

    ComputePipeline& p = ctx_.pipeline(shader, uint32_t(buffers.size()), push_bytes);
    if (p.buffer_count() != buffers.size() || p.push_bytes() != push_bytes)
        throw std::logic_error("shader " + shader + " used with a different binding count or push size");
    vkCmdBindPipeline(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, p.handle());

    const auto& info = ctx_.info();
    std::vector<VkDescriptorBufferInfo> infos;
    std::vector<VkBufferView> views;
    std::vector<VkWriteDescriptorSet> writes;
    infos.reserve(buffers.size());
    views.reserve(buffers.size());
    uint32_t binding = 0;
    for (auto& r : buffers) {
        const BindingKind& kind = p.bindings()[binding];
        const VkDeviceSize size = r.size == VK_WHOLE_SIZE ? r.buffer->size() - r.offset : r.size;
        VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        w.dstBinding = binding++;
        w.descriptorCount = 1;
        w.descriptorType = kind.type;
        if (kind.type == VK_DESCRIPTOR_TYPE_STORAGE_BUFFER) {
            if (size > info.max_storage_buffer_range)
                throw std::runtime_error("buffer '" + r.buffer->name() + "' binding of " + std::to_string(size) +
                                         " bytes exceeds the device's maxStorageBufferRange (" +
                                         std::to_string(info.max_storage_buffer_range) + ") in " + shader);
            infos.push_back({r.buffer->handle(), r.offset, size});
            w.pBufferInfo = &infos.back();
        } else {
            // A range that is not a whole number of texels ends at the last whole one.
            const VkDeviceSize texels = size / kind.texel_bytes;
            if (texels > info.max_texel_buffer_elements)
                throw std::runtime_error("buffer '" + r.buffer->name() + "' binding of " + std::to_string(texels) +
                                         " texels exceeds the device's maxTexelBufferElements (" +
                                         std::to_string(info.max_texel_buffer_elements) + ") in " + shader);
            if (r.offset % info.min_texel_buffer_offset_alignment != 0 || texels == 0)
                throw std::logic_error("texel buffer '" + r.buffer->name() + "' bound at offset " +
                                       std::to_string(r.offset) + " with " + std::to_string(size) + " bytes in " + shader);
            views.push_back(r.buffer->texel_view(kind.format, r.offset, texels * kind.texel_bytes));
            w.pTexelBufferView = &views.back();
        }
        writes.push_back(w);
    }
    if (!writes.empty())
        ctx_.push_descriptor_fn(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, p.layout(), 0, uint32_t(writes.size()),
                                writes.data());
    if (push_bytes) vkCmdPushConstants(cmd_, p.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, push_bytes, push);
    return p;
}

void CommandList::dispatch_raw(const std::string& shader, std::span<const BufferRange> buffers,
                               const void* push, uint32_t push_bytes, uint64_t groups_x, uint32_t groups_y) {
    if (groups_x == 0 || groups_y == 0) return;
    bind(shader, buffers, push, push_bytes);
    const uint64_t limit = ctx_.max_group_count_x();
    if (groups_y == 1 && groups_x > limit) {
        uint64_t rows = ceil_div(groups_x, limit);
        if (rows > ctx_.info().max_group_count[1])
            throw std::runtime_error(shader + ": dispatch of " + std::to_string(groups_x) + " groups is too large");
        // Folded grid: the shader skips the ids past groups_x in the last row.
        vkCmdDispatch(cmd_, uint32_t(limit), uint32_t(rows), 1);
    } else {
        if (groups_x > limit || groups_y > ctx_.info().max_group_count[1])
            throw std::runtime_error(shader + ": 2D dispatch exceeds the device's group-count limit");
        vkCmdDispatch(cmd_, uint32_t(groups_x), groups_y, 1);
    }
    ++dispatches_;
}

void CommandList::dispatch_indirect_raw(const std::string& shader, std::span<const BufferRange> buffers,
                                        const void* push, uint32_t push_bytes, const Buffer& args,
                                        VkDeviceSize offset) {
    begin_if_needed();
    if (std::find(touched_.begin(), touched_.end(), args.handle()) != touched_.end()) barrier();
    bind(shader, buffers, push, push_bytes);
    if (std::find(touched_.begin(), touched_.end(), args.handle()) == touched_.end()) touched_.push_back(args.handle());
    vkCmdDispatchIndirect(cmd_, args.handle(), offset);
    ++dispatches_;
}

void CommandList::fill(const Buffer& dst, uint32_t value, VkDeviceSize offset, VkDeviceSize bytes) {
    begin_if_needed();
    touch(dst);
    if (bytes == VK_WHOLE_SIZE) bytes = dst.size() - offset;
    bytes &= ~VkDeviceSize(3);
    if (bytes) vkCmdFillBuffer(cmd_, dst.handle(), offset, bytes, value);
}

void CommandList::copy(const Buffer& src, const Buffer& dst, VkDeviceSize bytes, VkDeviceSize src_offset,
                       VkDeviceSize dst_offset) {
    begin_if_needed();
    touch(src);
    if (dst.handle() != src.handle()) touch(dst);
    if (!bytes) return;
    VkBufferCopy region{src_offset, dst_offset, bytes};
    vkCmdCopyBuffer(cmd_, src.handle(), dst.handle(), 1, &region);
}

void CommandList::update(const Buffer& dst, const void* data, VkDeviceSize bytes, VkDeviceSize offset) {
    begin_if_needed();
    touch(dst);
    if (bytes) vkCmdUpdateBuffer(cmd_, dst.handle(), offset, bytes, data);
}

void CommandList::begin_pass(const std::string& name) {
    begin_if_needed();
    if (pass_open_) end_pass();
    if (!queries_ || 2 * (pass_names_.size() + 1) > kMaxQueries) return;
    vkCmdWriteTimestamp(cmd_, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, queries_, uint32_t(2 * pass_names_.size()));
    pass_names_.push_back(name);
    pass_open_ = true;
}

void CommandList::end_pass() {
    if (!pass_open_) return;
    vkCmdWriteTimestamp(cmd_, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, queries_, uint32_t(2 * pass_names_.size() - 1));
    pass_open_ = false;
}

void CommandList::submit_and_wait() {
    begin_if_needed();
    end_pass();
    // Make every write visible to the host reading mapped memory after the fence.
    VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    mb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &mb, 0, nullptr, 0, nullptr);
    PG_VK(vkEndCommandBuffer(cmd_));
    recording_ = false;
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cmd_;
    {
        std::lock_guard lock(ctx_.queue_mutex());
        check(ctx_.queue_submit(si, fence_), "vkQueueSubmit");
    }
    PG_VK(vkWaitForFences(ctx_.device(), 1, &fence_, VK_TRUE, UINT64_MAX));
    PG_VK(vkResetFences(ctx_.device(), 1, &fence_));

    timings_.clear();
    if (queries_ && !pass_names_.empty()) {
        std::vector<uint64_t> stamps(2 * pass_names_.size());
        PG_VK(vkGetQueryPoolResults(ctx_.device(), queries_, 0, uint32_t(stamps.size()),
                                    stamps.size() * sizeof(uint64_t), stamps.data(), sizeof(uint64_t),
                                    VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
        double ns = ctx_.info().timestamp_period_ns;
        for (size_t i = 0; i < pass_names_.size(); ++i)
            timings_.push_back({pass_names_[i], double(stamps[2 * i + 1] - stamps[2 * i]) * ns * 1e-6});
    }
    PG_VK(vkResetCommandBuffer(cmd_, 0));
}

double CommandList::total_ms() const {
    double t = 0;
    for (auto& p : timings_) t += p.ms;
    return t;
}

}  // namespace pg::vk

#include "engine/vk/buffer.h"

#include <algorithm>
#include <atomic>
#include <mutex>
#include <stdexcept>
#include <utility>

#include "engine/vk/check.h"
#include "engine/vk/commands.h"
#include "engine/vk/context.h"

namespace pg::vk {

namespace {
std::atomic<uint64_t> g_live{0}, g_peak{0};

void count_alloc(uint64_t bytes) {
    uint64_t live = g_live.fetch_add(bytes) + bytes;
    uint64_t peak = g_peak.load();
    while (live > peak && !g_peak.compare_exchange_weak(peak, live)) {}
}
}  // namespace

MemoryStats memory_stats() { return {g_live.load(), g_peak.load()}; }
void reset_peak_memory() { g_peak.store(g_live.load()); }

Buffer::Buffer(Context& ctx, VkDeviceSize bytes, MemoryUse use, std::string name)
    : ctx_(&ctx), use_(use), name_(std::move(name)) {
    ensure(bytes);
}

Buffer::~Buffer() { release(); }

Buffer& Buffer::operator=(Buffer&& o) noexcept {
    if (this != &o) {
        release();
        ctx_ = o.ctx_;
        buffer_ = std::exchange(o.buffer_, VK_NULL_HANDLE);
        memory_ = std::exchange(o.memory_, VK_NULL_HANDLE);
        size_ = std::exchange(o.size_, 0);
        mapped_ = std::exchange(o.mapped_, nullptr);
        use_ = o.use_;
        name_ = std::move(o.name_);
        views_ = std::exchange(o.views_, {});
    }
    return *this;
}

void Buffer::release() {
    if (!ctx_) return;
    VkDevice dev = ctx_->device();
    for (const View& v : views_) vkDestroyBufferView(dev, v.view, nullptr);
    views_.clear();
    if (buffer_) vkDestroyBuffer(dev, buffer_, nullptr);
    if (memory_) {
        vkFreeMemory(dev, memory_, nullptr);
        g_live.fetch_sub(size_);
    }
    buffer_ = VK_NULL_HANDLE;
    memory_ = VK_NULL_HANDLE;
    mapped_ = nullptr;
    size_ = 0;
}

VkBufferView Buffer::texel_view(VkFormat format, VkDeviceSize offset, VkDeviceSize bytes) const {
    // Command lists of different threads (a viewer's render and segmentation) may bind one buffer.
    static std::mutex views_mutex;
    std::lock_guard lock(views_mutex);
    for (const View& v : views_)
        if (v.format == format && v.offset == offset && v.bytes == bytes) return v.view;
    VkBufferViewCreateInfo vci{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
    vci.buffer = buffer_;
    vci.format = format;
    vci.offset = offset;
    vci.range = bytes;
    VkBufferView view;
    PG_VK(vkCreateBufferView(ctx_->device(), &vci, nullptr, &view));
    views_.push_back({format, offset, bytes, view});
    return view;
}

void Buffer::ensure(VkDeviceSize bytes) {
    if (buffer_ && bytes <= size_) return;
    if (!ctx_) throw std::logic_error("Buffer::ensure on a buffer without a context");
    release();
    // Vulkan forbids empty buffers; a small one keeps bindings valid for empty inputs.
    VkDeviceSize alloc = std::max<VkDeviceSize>((bytes + 15) & ~VkDeviceSize(15), 16);
    const auto& info = ctx_->info();
    if (alloc > info.max_buffer_size || alloc > info.max_allocation_size)
        throw std::runtime_error("buffer '" + name_ + "' of " + std::to_string(alloc) + " bytes exceeds what " +
                                 info.name + " can allocate (" +
                                 std::to_string(std::min(info.max_buffer_size, info.max_allocation_size)) + " bytes)");

    VkBufferCreateInfo bci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bci.size = alloc;
    bci.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
                VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT;
    bci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    VkDevice dev = ctx_->device();
    PG_VK(vkCreateBuffer(dev, &bci, nullptr, &buffer_));

    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(dev, buffer_, &req);
    VkMemoryPropertyFlags required = 0, preferred = 0;
    switch (use_) {
        case MemoryUse::Device:
            required = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
            if (info.unified_memory) preferred = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
            break;
        case MemoryUse::Upload:
            required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
            break;
        case MemoryUse::Readback:
            required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
            preferred = VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
            break;
    }
    uint32_t type = ctx_->find_memory_type(req.memoryTypeBits, required, preferred);
    VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    mai.allocationSize = req.size;
    mai.memoryTypeIndex = type;
    VkResult r = ctx_->allocation_fault() ? VK_ERROR_OUT_OF_DEVICE_MEMORY : vkAllocateMemory(dev, &mai, nullptr, &memory_);
    if (r != VK_SUCCESS) {
        vkDestroyBuffer(dev, buffer_, nullptr);
        buffer_ = VK_NULL_HANDLE;
        throw VulkanError("allocating " + std::to_string(alloc) + " bytes for buffer '" + name_ + "'", r);
    }
    PG_VK(vkBindBufferMemory(dev, buffer_, memory_, 0));
    size_ = alloc;
    count_alloc(size_);
    VkMemoryPropertyFlags flags = 0;
    VkPhysicalDeviceMemoryProperties mp;
    vkGetPhysicalDeviceMemoryProperties(ctx_->physical_device(), &mp);
    flags = mp.memoryTypes[type].propertyFlags;
    // Device buffers are mapped only on unified memory: elsewhere (or when a discrete GPU is
    // emulated) host access goes through staging copies.
    const bool host_access = use_ != MemoryUse::Device || info.unified_memory;
    if (host_access && (flags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) && (flags & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT))
        PG_VK(vkMapMemory(dev, memory_, 0, VK_WHOLE_SIZE, 0, &mapped_));
}

namespace {
// Staging memory and a command list kept by the context for the copies that need them (a
// discrete GPU's device-local buffers): a copy per call used to allocate both, and on an NVIDIA
// driver that cost more than the copy. Transfers larger than the staging buffer go in chunks,
// so what stays allocated is bounded.
struct StagedTransfers {
    static constexpr VkDeviceSize kChunk = VkDeviceSize(32) << 20;
    explicit StagedTransfers(Context& ctx) : down(ctx, 16, MemoryUse::Readback, "readback"), cmd(ctx) {}
    std::mutex mutex;
    Buffer down;     // uploads stage in cmd's own memory (CommandList::upload)
    CommandList cmd;
};

StagedTransfers& staged(Context& ctx) { return ctx.attachment<StagedTransfers>("vk staged transfers"); }
}  // namespace

void upload(Context& ctx, Buffer& dst, const void* src, VkDeviceSize bytes, VkDeviceSize offset) {
    if (offset + bytes > dst.size()) throw std::out_of_range("upload past the end of buffer '" + dst.name() + "'");
    if (dst.mapped()) {
        std::memcpy(static_cast<char*>(dst.data()) + offset, src, bytes);
        return;
    }
    StagedTransfers& t = staged(ctx);
    std::lock_guard lock(t.mutex);
    for (VkDeviceSize done = 0; done < bytes;) {
        const VkDeviceSize n = std::min(bytes - done, StagedTransfers::kChunk);
        t.cmd.upload(dst, static_cast<const char*>(src) + done, n, offset + done);
        t.cmd.submit_and_wait();
        done += n;
    }
}

void download(Context& ctx, const Buffer& src, void* dst, VkDeviceSize bytes, VkDeviceSize offset) {
    if (offset + bytes > src.size()) throw std::out_of_range("download past the end of buffer '" + src.name() + "'");
    if (src.mapped()) {
        std::memcpy(dst, static_cast<const char*>(src.data()) + offset, bytes);
        return;
    }
    StagedTransfers& t = staged(ctx);
    std::lock_guard lock(t.mutex);
    for (VkDeviceSize done = 0; done < bytes;) {
        const VkDeviceSize n = std::min(bytes - done, StagedTransfers::kChunk);
        t.down.ensure(n);
        t.cmd.copy(src, t.down, n, offset + done, 0);
        t.cmd.submit_and_wait();
        std::memcpy(static_cast<char*>(dst) + done, t.down.data(), n);
        done += n;
    }
}

}  // namespace pg::vk

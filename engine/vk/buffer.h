#pragma once
// Buffers with 64-bit sizes. Device buffers live in device-local memory; on unified-memory
// devices (lavapipe, many iGPUs) they are also mapped, and uploads skip the staging copy.
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace pg::vk {

class Context;

enum class MemoryUse { Device, Upload, Readback };

class Buffer {
public:
    Buffer() = default;
    Buffer(Context& ctx, VkDeviceSize bytes, MemoryUse use = MemoryUse::Device, std::string name = {});
    ~Buffer();
    Buffer(Buffer&& o) noexcept { *this = std::move(o); }
    Buffer& operator=(Buffer&& o) noexcept;
    Buffer(const Buffer&) = delete;
    Buffer& operator=(const Buffer&) = delete;

    VkBuffer handle() const { return buffer_; }
    VkDeviceSize size() const { return size_; }
    bool valid() const { return buffer_ != VK_NULL_HANDLE; }
    bool mapped() const { return mapped_ != nullptr; }
    void* data() const { return mapped_; }
    template <class T> T* as() const { return static_cast<T*>(mapped_); }
    const std::string& name() const { return name_; }

    // Grows (never shrinks) to hold at least `bytes`; contents are not kept.
    void ensure(VkDeviceSize bytes);

    // A texel-buffer view of [offset, offset + bytes) in `format`, made on first use and kept
    // while the buffer lives.
    VkBufferView texel_view(VkFormat format, VkDeviceSize offset, VkDeviceSize bytes) const;

private:
    void release();
    Context* ctx_ = nullptr;
    VkBuffer buffer_ = VK_NULL_HANDLE;
    VkDeviceMemory memory_ = VK_NULL_HANDLE;
    VkDeviceSize size_ = 0;
    void* mapped_ = nullptr;
    MemoryUse use_ = MemoryUse::Device;
    std::string name_;
    struct View {
        VkFormat format;
        VkDeviceSize offset, bytes;
        VkBufferView view;
    };
    mutable std::vector<View> views_;
};

// Host <-> device copies that go through a staging buffer only when the memory is not mapped.
void upload(Context& ctx, Buffer& dst, const void* src, VkDeviceSize bytes, VkDeviceSize offset = 0);
void download(Context& ctx, const Buffer& src, void* dst, VkDeviceSize bytes, VkDeviceSize offset = 0);

template <class T> Buffer upload_vector(Context& ctx, const std::vector<T>& v, std::string name = {}) {
    Buffer b(ctx, v.size() * sizeof(T), MemoryUse::Device, std::move(name));
    if (!v.empty()) upload(ctx, b, v.data(), v.size() * sizeof(T));
    return b;
}
template <class T> std::vector<T> download_vector(Context& ctx, const Buffer& b, size_t count, VkDeviceSize offset = 0) {
    std::vector<T> v(count);
    if (count) download(ctx, b, v.data(), count * sizeof(T), offset);
    return v;
}

// Live and peak bytes of all buffers of all contexts, for `bench` memory figures.
struct MemoryStats { uint64_t live = 0, peak = 0; };
MemoryStats memory_stats();
void reset_peak_memory();

}  // namespace pg::vk

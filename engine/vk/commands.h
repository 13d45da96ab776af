#pragma once
// Records compute work into one command buffer. Barriers are inserted automatically: a
// command that touches a buffer already touched since the last barrier gets one first, so
// passes never write barriers by hand. Named passes get GPU timestamps.
#include <cstdint>
#include <initializer_list>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/vk/buffer.h"

namespace pg::vk {

class Context;
class ComputePipeline;

// A buffer or a window of one, as bound to a shader.
struct BufferRange {
    BufferRange(const Buffer& b) : buffer(&b) {}  // NOLINT: implicit on purpose, the common case
    BufferRange(const Buffer& b, VkDeviceSize off, VkDeviceSize len) : buffer(&b), offset(off), size(len) {}
    const Buffer* buffer;
    VkDeviceSize offset = 0;
    VkDeviceSize size = VK_WHOLE_SIZE;
};

// Workgroups of `per_group` invocations covering n items (or tiles, blocks, chunks of a size):
// the rounding-up division behind every dispatch, in one place. Counts fit 32 bits, as the
// shaders index in 32 bits.
constexpr uint32_t ceil_div(uint64_t n, uint64_t per_group) { return uint32_t((n + per_group - 1) / per_group); }

struct PassTiming {
    std::string name;
    double ms;
};

class CommandList {
public:
    explicit CommandList(Context& ctx);
    ~CommandList();
    CommandList(const CommandList&) = delete;
    CommandList& operator=(const CommandList&) = delete;

    // `groups` workgroups along x; counts over the device limit are folded into y, which the
    // shader undoes with pg_group_index() from shaders/common/dispatch.glsl.
    template <class Push>
    void dispatch(const std::string& shader, std::initializer_list<BufferRange> buffers, const Push& push, uint64_t groups) {
        dispatch_raw(shader, list(buffers), &push, sizeof(Push), groups, 1);
    }
    // The same with the bindings in an array: a count the caller builds up (nn/adamw's sets of tensors).
    template <class Push>
    void dispatch(const std::string& shader, std::span<const BufferRange> buffers, const Push& push, uint64_t groups) {
        dispatch_raw(shader, buffers, &push, sizeof(Push), groups, 1);
    }
    void dispatch(const std::string& shader, std::initializer_list<BufferRange> buffers, uint64_t groups) {
        dispatch_raw(shader, list(buffers), nullptr, 0, groups, 1);
    }
    // A 2D grid (e.g. image tiles); each dimension must be within the device limit.
    template <class Push>
    void dispatch_2d(const std::string& shader, std::initializer_list<BufferRange> buffers, const Push& push,
                     uint32_t groups_x, uint32_t groups_y) {
        dispatch_raw(shader, list(buffers), &push, sizeof(Push), groups_x, groups_y);
    }
    void dispatch_2d(const std::string& shader, std::initializer_list<BufferRange> buffers, uint32_t groups_x,
                     uint32_t groups_y) {
        dispatch_raw(shader, list(buffers), nullptr, 0, groups_x, groups_y);
    }
    // Group counts read from `args` at `offset` (three uints, written by an earlier pass).
    template <class Push>
    void dispatch_indirect(const std::string& shader, std::initializer_list<BufferRange> buffers, const Push& push,
                           const Buffer& args, VkDeviceSize offset = 0) {
        dispatch_indirect_raw(shader, list(buffers), &push, sizeof(Push), args, offset);
    }

    void dispatch_indirect(const std::string& shader, std::initializer_list<BufferRange> buffers, const Buffer& args,
                           VkDeviceSize offset = 0) {
        dispatch_indirect_raw(shader, list(buffers), nullptr, 0, args, offset);
    }

    void fill(const Buffer& dst, uint32_t value, VkDeviceSize offset = 0, VkDeviceSize bytes = VK_WHOLE_SIZE);
    void copy(const Buffer& src, const Buffer& dst, VkDeviceSize bytes, VkDeviceSize src_offset = 0,
              VkDeviceSize dst_offset = 0);
    void update(const Buffer& dst, const void* data, VkDeviceSize bytes, VkDeviceSize offset = 0);  // <= 64 KiB
    // Host data into dst as part of this list: a mapped dst is written at once (so no command
    // recorded earlier in this list may use it), any other is staged in the list's own memory
    // and copied when the list runs. Many uploads then cost one submission, not one each.
    void upload(const Buffer& dst, const void* data, VkDeviceSize bytes, VkDeviceSize offset = 0);
    // A full memory barrier, for work the tracker cannot see (rarely needed).
    void barrier();

    // Starts a named pass; it ends where the next one starts or at end_pass().
    void begin_pass(const std::string& name);
    void end_pass();

    // Submits, waits for the GPU and resets for reuse. Timings of the named passes follow.
    void submit_and_wait();
    const std::vector<PassTiming>& timings() const { return timings_; }
    double total_ms() const;

    uint64_t dispatch_count() const { return dispatches_; }

private:
    void begin_if_needed();
    void touch(const Buffer& b);
    static std::span<const BufferRange> list(std::initializer_list<BufferRange> buffers) {
        return {buffers.begin(), buffers.size()};
    }
    void dispatch_raw(const std::string& shader, std::span<const BufferRange> buffers, const void* push,
                      uint32_t push_bytes, uint64_t groups_x, uint32_t groups_y);
    void dispatch_indirect_raw(const std::string& shader, std::span<const BufferRange> buffers, const void* push,
                               uint32_t push_bytes, const Buffer& args, VkDeviceSize offset);
    ComputePipeline& bind(const std::string& shader, std::span<const BufferRange> buffers, const void* push,
                          uint32_t push_bytes);

    Context& ctx_;
    VkCommandPool pool_ = VK_NULL_HANDLE;
    VkCommandBuffer cmd_ = VK_NULL_HANDLE;
    VkFence fence_ = VK_NULL_HANDLE;
    VkQueryPool queries_ = VK_NULL_HANDLE;
    bool recording_ = false;
    std::vector<VkBuffer> touched_;
    std::vector<std::string> pass_names_;
    bool pass_open_ = false;
    std::vector<PassTiming> timings_;
    uint64_t dispatches_ = 0;
    std::vector<Buffer> staging_;              // upload()'s host-visible chunks, kept for reuse
    std::vector<VkDeviceSize> staging_used_;   // bytes of each chunk taken since the last submit
    static constexpr uint32_t kMaxQueries = 4096;  // a PTv3 forward times ~1000 passes
};

}  // namespace pg::vk

#pragma once
// The Vulkan instance, the chosen device and its compute queue: no window system needed.
#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace pg::vk {

class ComputePipeline;

struct ContextOptions {
    std::string device;       // substring of the device name; empty: PG_DEVICE, else best
    bool validation = false;  // Khronos validation (also on with PG_VALIDATION=1)
    bool quiet = false;       // do not print the chosen device
    // Tests lower this to exercise dispatch splitting cheaply; 0 = the device's limit.
    uint32_t max_group_count_override = 0;
    // Treat the device as a discrete GPU's memory (also with PG_DISCRETE_MEMORY=1): device
    // buffers are never mapped, every transfer goes through staging copies, so lavapipe runs
    // the code paths a real GPU takes.
    bool discrete_memory = false;
    // Fault injection for tests (also PG_FAULT_DEVICE_ALLOCATIONS=N): the allocations after the
    // first N fail as VK_ERROR_OUT_OF_DEVICE_MEMORY would. -1: none fail.
    int64_t fail_allocations_after = -1;
    // The same for queue submissions (also PG_FAULT_DEVICE_SUBMITS=N): a driver may report a full
    // device there too, after every allocation succeeded.
    int64_t fail_submits_after = -1;
    // For a window (the viewer): extra instance extensions (GLFW's), and a test of whether a
    // queue family can present; the device then also needs VK_KHR_swapchain.
    std::vector<std::string> instance_extensions;
    std::function<bool(VkInstance, VkPhysicalDevice, uint32_t family)> can_present;
};

struct DeviceInfo {
    std::string name;
    VkPhysicalDeviceType type;
    uint32_t api_version;
    VkDeviceSize max_storage_buffer_range;
    uint32_t max_texel_buffer_elements;
    VkDeviceSize min_texel_buffer_offset_alignment;
    VkDeviceSize max_allocation_size;
    VkDeviceSize max_buffer_size;
    uint32_t max_group_count[3];
    uint32_t max_shared_memory;
    uint32_t subgroup_size;
    float timestamp_period_ns;
    bool timestamps;
    bool unified_memory;  // every device-local heap is host-visible (lavapipe, some iGPUs), unless
                          // ContextOptions::discrete_memory says to act as if not
    VkDeviceSize device_memory_bytes;
};

std::string device_type_name(VkPhysicalDeviceType t);

class Context {
public:
    explicit Context(const ContextOptions& options = {});
    ~Context();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    VkInstance instance() const { return instance_; }
    VkPhysicalDevice physical_device() const { return physical_; }
    VkDevice device() const { return device_; }
    VkQueue queue() const { return queue_; }
    uint32_t queue_family() const { return queue_family_; }
    const DeviceInfo& info() const { return info_; }
    uint32_t max_group_count_x() const;

    uint32_t find_memory_type(uint32_t type_bits, VkMemoryPropertyFlags required, VkMemoryPropertyFlags preferred) const;

    // Pipelines are built once per shader name and kept for the context's life.
    ComputePipeline& pipeline(const std::string& shader, uint32_t buffer_count, uint32_t push_bytes);
    std::vector<std::string> pipeline_names();  // those built so far, sorted

    // The queue is shared by every thread (the viewer renders and segments at once): hold this
    // around vkQueueSubmit and vkQueuePresentKHR.
    std::mutex& queue_mutex() { return queue_mutex_; }

    // State owned by the context, made on first use by T(Context&) and destroyed before the
    // device: scratch buffers of ops that are free functions (they must outlive the command
    // lists they were recorded into, so they cannot be locals).
    template <class T> T& attachment(const std::string& key) {
        std::lock_guard lock(attachments_mutex_);
        auto& slot = attachments_[key];
        if (!slot) slot = std::make_shared<T>(*this);
        return *static_cast<T*>(slot.get());
    }
    void detach(const std::string& key) {
        std::lock_guard lock(attachments_mutex_);
        attachments_.erase(key);
    }

    // True when this device memory allocation is to fail (ContextOptions::fail_allocations_after).
    bool allocation_fault() {
        return options_.fail_allocations_after >= 0 && allocations_.fetch_add(1) >= options_.fail_allocations_after;
    }

    // vkQueueSubmit on the queue, or VK_ERROR_OUT_OF_DEVICE_MEMORY where the fault injection
    // (ContextOptions::fail_submits_after) says this submission fails. Every submission goes
    // through here. The caller holds queue_mutex().
    VkResult queue_submit(const VkSubmitInfo& info, VkFence fence) {
        if (options_.fail_submits_after >= 0 && submits_.fetch_add(1) >= options_.fail_submits_after)
            return VK_ERROR_OUT_OF_DEVICE_MEMORY;
        return vkQueueSubmit(queue_, 1, &info, fence);
    }

    // Validation messages seen so far (warnings and errors); tests fail when non-zero.
    static uint64_t validation_message_count();

    PFN_vkCmdPushDescriptorSetKHR push_descriptor_fn = nullptr;

    // Every device the loader sees, for `--device` help and errors.
    static std::vector<std::string> list_devices();

private:
    void create_instance(bool validation);
    void pick_device(const std::string& wanted);
    void create_device();
    // A compute + graphics queue family that can present, or -1.
    int present_family(VkPhysicalDevice pd) const;

    std::mutex attachments_mutex_, queue_mutex_;
    std::atomic<int64_t> allocations_{0}, submits_{0};
    std::map<std::string, std::shared_ptr<void>> attachments_;
    VkInstance instance_ = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
    VkPhysicalDevice physical_ = VK_NULL_HANDLE;
    VkDevice device_ = VK_NULL_HANDLE;
    VkQueue queue_ = VK_NULL_HANDLE;
    uint32_t queue_family_ = 0;
    DeviceInfo info_{};
    VkPhysicalDeviceMemoryProperties memory_{};
    ContextOptions options_;
    std::mutex pipelines_mutex_;
    std::map<std::string, std::unique_ptr<ComputePipeline>> pipelines_;
};

}  // namespace pg::vk

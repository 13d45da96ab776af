#pragma once
// Puts a frame on the window: the engine's picture (RGBA8 in a device buffer, any size) is
// copied into an image and blitted into a window-sized target image with letterboxing, Dear ImGui draws over it, and the target is blitted to
// the swapchain. The target, not the swapchain image, is what screenshots read, so they do not
// depend on the window system's formats.
#include <cstdint>
#include <memory>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/vk/buffer.h"
#include "engine/vk/context.h"

namespace pg::viewer {

struct Rect {
    int x = 0, y = 0, width = 0, height = 0;
};

class Presenter {
public:
    Presenter(vk::Context& ctx, VkSurfaceKHR surface, int width, int height);
    ~Presenter();
    Presenter(const Presenter&) = delete;
    Presenter& operator=(const Presenter&) = delete;

    VkRenderPass render_pass() const { return render_pass_; }
    uint32_t image_count() const { return uint32_t(swap_images_.size()); }

    // The next picture to show (written by a compute pass on this queue); the image keeps it
    // until replaced, the buffer is let go once copied.
    void set_picture(std::shared_ptr<const vk::Buffer> rgba, int width, int height);
    // Where the picture goes (window pixels); it keeps its aspect ratio inside.
    void set_viewport(Rect r) { viewport_ = r; }
    Rect picture_rect() const;  // the letterboxed rectangle the picture occupies

    // Draws one frame; `draw_ui` records ImGui into the command buffer inside the render pass.
    // With `capture`, the finished target (RGBA8, window size) is copied into `captured`.
    // Returns false when the window has no area (minimised).
    template <class F> bool present(int width, int height, F&& draw_ui, bool capture = false) {
        struct Thunk : UiRecorder {
            F& f;
            explicit Thunk(F& f) : f(f) {}
            void record(VkCommandBuffer cmd) override { f(cmd); }
        } thunk(draw_ui);
        return present_impl(width, height, thunk, capture);
    }
    const std::vector<uint8_t>& captured() const { return captured_; }
    int captured_width() const { return target_width_; }
    int captured_height() const { return target_height_; }

    // Runs `record` once on the queue and waits (font upload).
    template <class F> void run_once(F&& record) {
        VkCommandBuffer cmd = begin_once();
        record(cmd);
        end_once(cmd);
    }

private:
    struct UiRecorder {
        virtual ~UiRecorder() = default;
        virtual void record(VkCommandBuffer cmd) = 0;
    };
    bool present_impl(int width, int height, UiRecorder& ui, bool capture);
    void create_swapchain(int width, int height);
    void destroy_swapchain();
    void create_target(int width, int height);
    void destroy_target();
    VkCommandBuffer begin_once();
    void end_once(VkCommandBuffer cmd);

    vk::Context& ctx_;
    VkDevice device_;
    VkSurfaceKHR surface_;
    VkSurfaceFormatKHR format_{};
    VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
    std::vector<VkImage> swap_images_;
    int swap_width_ = 0, swap_height_ = 0;

    VkRenderPass render_pass_ = VK_NULL_HANDLE;
    VkImage target_ = VK_NULL_HANDLE;
    VkDeviceMemory target_memory_ = VK_NULL_HANDLE;
    VkImageView target_view_ = VK_NULL_HANDLE;
    VkFramebuffer framebuffer_ = VK_NULL_HANDLE;
    int target_width_ = 0, target_height_ = 0;

    VkImage picture_ = VK_NULL_HANDLE;
    VkDeviceMemory picture_memory_ = VK_NULL_HANDLE;
    int picture_width_ = 0, picture_height_ = 0;
    std::shared_ptr<const vk::Buffer> picture_pending_;
    bool picture_ready_ = false;
    vk::Buffer readback_;
    std::vector<uint8_t> captured_;
    Rect viewport_;

    VkCommandPool pool_ = VK_NULL_HANDLE;
    VkCommandBuffer cmd_ = VK_NULL_HANDLE;
    VkFence fence_ = VK_NULL_HANDLE;
    VkSemaphore acquired_ = VK_NULL_HANDLE, rendered_ = VK_NULL_HANDLE;
};

}  // namespace pg::viewer

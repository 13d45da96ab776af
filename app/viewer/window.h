#pragma once
// The GLFW window and the Vulkan context that can present to it.
#include <memory>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/vk/context.h"

struct GLFWwindow;

namespace pg::viewer {

class Window {
public:
    Window(const std::string& title, int width, int height);
    ~Window();
    Window(const Window&) = delete;
    Window& operator=(const Window&) = delete;

    // A context on a device that can present here (device choice as the CLI: --device, PG_DEVICE).
    std::unique_ptr<vk::Context> make_context(const std::string& device);
    VkSurfaceKHR surface() const { return surface_; }
    GLFWwindow* handle() const { return window_; }
    void framebuffer_size(int& width, int& height) const;
    bool should_close() const;
    void destroy_surface();  // before the context goes

    // Key presses (and repeats) since the last call, with their modifiers. Kept here because
    // Dear ImGui 1.86 sees only key state per frame and loses a tap shorter than a slow frame.
    struct KeyPress {
        int key, mods;
    };
    std::vector<KeyPress> take_key_presses();

private:
    GLFWwindow* window_ = nullptr;
    VkInstance instance_ = VK_NULL_HANDLE;
    VkSurfaceKHR surface_ = VK_NULL_HANDLE;
    std::vector<KeyPress> presses_;
};

}  // namespace pg::viewer

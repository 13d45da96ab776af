#include "app/viewer/window.h"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <stdexcept>

namespace pg::viewer {

namespace {
std::string glfw_error() {
    const char* text = nullptr;
    glfwGetError(&text);
    return text ? text : "unknown GLFW error";
}
}  // namespace

Window::Window(const std::string& title, int width, int height) {
    if (!glfwInit())
        throw std::runtime_error("cannot open a window: " + glfw_error() +
                                 " (no display? run under a desktop session or xvfb-run)");
    if (!glfwVulkanSupported()) {
        glfwTerminate();
        throw std::runtime_error("GLFW finds no Vulkan loader (apt-get install libvulkan1 mesa-vulkan-drivers)");
    }
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
    if (!window_) {
        std::string e = glfw_error();
        glfwTerminate();
        throw std::runtime_error("cannot create the window: " + e);
    }
    // Installed before Dear ImGui's backend, which chains to it.
    glfwSetWindowUserPointer(window_, this);
    glfwSetKeyCallback(window_, [](GLFWwindow* w, int key, int, int action, int mods) {
        if (action != GLFW_RELEASE) static_cast<Window*>(glfwGetWindowUserPointer(w))->presses_.push_back({key, mods});
    });
}

std::vector<Window::KeyPress> Window::take_key_presses() {
    std::vector<KeyPress> out;
    out.swap(presses_);
    return out;
}

Window::~Window() {
    if (window_) glfwDestroyWindow(window_);
    glfwTerminate();
}

std::unique_ptr<vk::Context> Window::make_context(const std::string& device) {
    vk::ContextOptions o;
    o.device = device;
    uint32_t n = 0;
    const char** exts = glfwGetRequiredInstanceExtensions(&n);
    for (uint32_t i = 0; i < n; ++i) o.instance_extensions.push_back(exts[i]);
    o.can_present = [](VkInstance instance, VkPhysicalDevice pd, uint32_t family) {
        return glfwGetPhysicalDevicePresentationSupport(instance, pd, family) == GLFW_TRUE;
    };
    auto ctx = std::make_unique<vk::Context>(o);
    instance_ = ctx->instance();
    if (VkResult r = glfwCreateWindowSurface(instance_, window_, nullptr, &surface_); r != VK_SUCCESS)
        throw std::runtime_error("cannot create a Vulkan surface for the window (VkResult " + std::to_string(r) + ")");
    return ctx;
}

void Window::destroy_surface() {
    if (surface_) vkDestroySurfaceKHR(instance_, surface_, nullptr);
    surface_ = VK_NULL_HANDLE;
}

void Window::framebuffer_size(int& width, int& height) const { glfwGetFramebufferSize(window_, &width, &height); }

bool Window::should_close() const { return glfwWindowShouldClose(window_); }

}  // namespace pg::viewer

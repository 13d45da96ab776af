#pragma once
// Dear ImGui on GLFW input and the presenter's render pass (the backends Debian's libimgui ships).
#include <vulkan/vulkan.h>

#include "app/viewer/presenter.h"
#include "engine/vk/context.h"

struct GLFWwindow;

namespace pg::viewer {

class ImGuiLayer {
public:
    ImGuiLayer(vk::Context& ctx, GLFWwindow* window, Presenter& presenter);
    ~ImGuiLayer();
    ImGuiLayer(const ImGuiLayer&) = delete;
    ImGuiLayer& operator=(const ImGuiLayer&) = delete;

    void begin_frame();
    void end_frame();
    void record(VkCommandBuffer cmd);

private:
    vk::Context& ctx_;
    VkDescriptorPool pool_ = VK_NULL_HANDLE;
};

}  // namespace pg::viewer

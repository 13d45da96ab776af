#include "app/viewer/presenter.h"

#include <algorithm>
#include <mutex>
#include <stdexcept>

#include "engine/vk/check.h"

namespace pg::viewer {

namespace {

constexpr VkFormat kTargetFormat = VK_FORMAT_R8G8B8A8_UNORM;

void image_barrier(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to, VkAccessFlags src_access,
                   VkAccessFlags dst_access, VkPipelineStageFlags src_stage, VkPipelineStageFlags dst_stage) {
    VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
    b.oldLayout = from;
    b.newLayout = to;
    b.srcAccessMask = src_access;
    b.dstAccessMask = dst_access;
    b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = image;
    b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdPipelineBarrier(cmd, src_stage, dst_stage, 0, 0, nullptr, 0, nullptr, 1, &b);
}

VkImageBlit blit_region(int sw, int sh, Rect dst) {
    VkImageBlit r{};
    r.srcSubresource = r.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    r.srcOffsets[1] = {sw, sh, 1};
    r.dstOffsets[0] = {dst.x, dst.y, 0};
    r.dstOffsets[1] = {dst.x + dst.width, dst.y + dst.height, 1};
    return r;
}

}  // namespace

Presenter::Presenter(vk::Context& ctx, VkSurfaceKHR surface, int width, int height)
    : ctx_(ctx), device_(ctx.device()), surface_(surface) {
    uint32_t n = 0;
    vkGetPhysicalDeviceSurfaceFormatsKHR(ctx.physical_device(), surface, &n, nullptr);
    std::vector<VkSurfaceFormatKHR> formats(n);
    vkGetPhysicalDeviceSurfaceFormatsKHR(ctx.physical_device(), surface, &n, formats.data());
    if (formats.empty()) throw std::runtime_error("the window surface offers no image format");
    format_ = formats.front();
    for (auto f : formats)  // UNORM: the picture's bytes are display values already
        if ((f.format == VK_FORMAT_B8G8R8A8_UNORM || f.format == VK_FORMAT_R8G8B8A8_UNORM) &&
            f.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR) {
            format_ = f;
            break;
        }
    VkFormatProperties fp;
    vkGetPhysicalDeviceFormatProperties(ctx.physical_device(), format_.format, &fp);
    if (!(fp.optimalTilingFeatures & VK_FORMAT_FEATURE_BLIT_DST_BIT))
        throw std::runtime_error("device " + ctx.info().name + " cannot blit into the window's image format");

    VkAttachmentDescription colour{};
    colour.format = kTargetFormat;
    colour.samples = VK_SAMPLE_COUNT_1_BIT;
    colour.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
    colour.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    colour.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    colour.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    colour.initialLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    colour.finalLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    VkAttachmentReference ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkSubpassDescription sub{};
    sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    sub.colorAttachmentCount = 1;
    sub.pColorAttachments = &ref;
    VkSubpassDependency deps[2]{};
    deps[0].srcSubpass = VK_SUBPASS_EXTERNAL;
    deps[0].dstSubpass = 0;
    deps[0].srcStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT;
    deps[0].dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    deps[0].srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    deps[0].dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    deps[1].srcSubpass = 0;
    deps[1].dstSubpass = VK_SUBPASS_EXTERNAL;
    deps[1].srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    deps[1].dstStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT;
    deps[1].srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    deps[1].dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
    VkRenderPassCreateInfo rp{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    rp.attachmentCount = 1;
    rp.pAttachments = &colour;
    rp.subpassCount = 1;
    rp.pSubpasses = &sub;
    rp.dependencyCount = 2;
    rp.pDependencies = deps;
    PG_VK(vkCreateRenderPass(device_, &rp, nullptr, &render_pass_));

    VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pci.queueFamilyIndex = ctx.queue_family();
    PG_VK(vkCreateCommandPool(device_, &pci, nullptr, &pool_));
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = pool_;
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    PG_VK(vkAllocateCommandBuffers(device_, &ai, &cmd_));
    VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    PG_VK(vkCreateFence(device_, &fci, nullptr, &fence_));
    VkSemaphoreCreateInfo sci{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    PG_VK(vkCreateSemaphore(device_, &sci, nullptr, &acquired_));
    PG_VK(vkCreateSemaphore(device_, &sci, nullptr, &rendered_));

    readback_ = vk::Buffer(ctx, 4, vk::MemoryUse::Readback, "viewer screenshot");
    create_swapchain(width, height);
}

Presenter::~Presenter() {
    {
        std::lock_guard lock(ctx_.queue_mutex());
        vkQueueWaitIdle(ctx_.queue());
    }
    destroy_target();
    destroy_swapchain();
    if (picture_) vkDestroyImage(device_, picture_, nullptr);
    if (picture_memory_) vkFreeMemory(device_, picture_memory_, nullptr);
    vkDestroySemaphore(device_, acquired_, nullptr);
    vkDestroySemaphore(device_, rendered_, nullptr);
    vkDestroyFence(device_, fence_, nullptr);
    vkDestroyCommandPool(device_, pool_, nullptr);
    vkDestroyRenderPass(device_, render_pass_, nullptr);
}

void Presenter::create_swapchain(int width, int height) {
    VkSurfaceCapabilitiesKHR caps;
    PG_VK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(ctx_.physical_device(), surface_, &caps));
    if (!(caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT))
        throw std::runtime_error("the window's images cannot be written by transfers on " + ctx_.info().name);
    VkExtent2D extent = caps.currentExtent;
    if (extent.width == 0xFFFFFFFFu) {
        extent.width = std::clamp(uint32_t(width), caps.minImageExtent.width, caps.maxImageExtent.width);
        extent.height = std::clamp(uint32_t(height), caps.minImageExtent.height, caps.maxImageExtent.height);
    }
    uint32_t count = caps.minImageCount + 1;
    if (caps.maxImageCount) count = std::min(count, caps.maxImageCount);
    VkSwapchainCreateInfoKHR ci{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
    ci.surface = surface_;
    ci.minImageCount = count;
    ci.imageFormat = format_.format;
    ci.imageColorSpace = format_.colorSpace;
    ci.imageExtent = extent;
    ci.imageArrayLayers = 1;
    ci.imageUsage = VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    ci.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
    ci.preTransform = caps.currentTransform;
    ci.compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
    if (!(caps.supportedCompositeAlpha & VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR))
        ci.compositeAlpha = VK_COMPOSITE_ALPHA_INHERIT_BIT_KHR;
    ci.presentMode = VK_PRESENT_MODE_FIFO_KHR;  // always available
    ci.clipped = VK_TRUE;
    ci.oldSwapchain = swapchain_;
    VkSwapchainKHR fresh;
    PG_VK(vkCreateSwapchainKHR(device_, &ci, nullptr, &fresh));
    destroy_swapchain();
    swapchain_ = fresh;
    swap_width_ = int(extent.width);
    swap_height_ = int(extent.height);
    uint32_t n = 0;
    vkGetSwapchainImagesKHR(device_, swapchain_, &n, nullptr);
    swap_images_.resize(n);
    vkGetSwapchainImagesKHR(device_, swapchain_, &n, swap_images_.data());
    create_target(swap_width_, swap_height_);
}

void Presenter::destroy_swapchain() {
    if (swapchain_) vkDestroySwapchainKHR(device_, swapchain_, nullptr);
    swapchain_ = VK_NULL_HANDLE;
    swap_images_.clear();
}

namespace {
void make_image(vk::Context& ctx, int w, int h, VkImageUsageFlags usage, VkImage& image, VkDeviceMemory& memory) {
    VkImageCreateInfo ci{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    ci.imageType = VK_IMAGE_TYPE_2D;
    ci.format = kTargetFormat;
    ci.extent = {uint32_t(w), uint32_t(h), 1};
    ci.mipLevels = ci.arrayLayers = 1;
    ci.samples = VK_SAMPLE_COUNT_1_BIT;
    ci.tiling = VK_IMAGE_TILING_OPTIMAL;
    ci.usage = usage;
    ci.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    PG_VK(vkCreateImage(ctx.device(), &ci, nullptr, &image));
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(ctx.device(), image, &req);
    VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    ai.allocationSize = req.size;
    ai.memoryTypeIndex = ctx.find_memory_type(req.memoryTypeBits, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    PG_VK(vkAllocateMemory(ctx.device(), &ai, nullptr, &memory));
    PG_VK(vkBindImageMemory(ctx.device(), image, memory, 0));
}
}  // namespace

void Presenter::create_target(int width, int height) {
    destroy_target();
    make_image(ctx_, width, height,
               VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
               target_, target_memory_);
    VkImageViewCreateInfo vi{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    vi.image = target_;
    vi.viewType = VK_IMAGE_VIEW_TYPE_2D;
    vi.format = kTargetFormat;
    vi.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    PG_VK(vkCreateImageView(device_, &vi, nullptr, &target_view_));
    VkFramebufferCreateInfo fi{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
    fi.renderPass = render_pass_;
    fi.attachmentCount = 1;
    fi.pAttachments = &target_view_;
    fi.width = uint32_t(width);
    fi.height = uint32_t(height);
    fi.layers = 1;
    PG_VK(vkCreateFramebuffer(device_, &fi, nullptr, &framebuffer_));
    target_width_ = width;
    target_height_ = height;
    readback_.ensure(uint64_t(width) * height * 4);
}

void Presenter::destroy_target() {
    if (framebuffer_) vkDestroyFramebuffer(device_, framebuffer_, nullptr);
    if (target_view_) vkDestroyImageView(device_, target_view_, nullptr);
    if (target_) vkDestroyImage(device_, target_, nullptr);
    if (target_memory_) vkFreeMemory(device_, target_memory_, nullptr);
    framebuffer_ = VK_NULL_HANDLE;
    target_view_ = VK_NULL_HANDLE;
    target_ = VK_NULL_HANDLE;
    target_memory_ = VK_NULL_HANDLE;
}

void Presenter::set_picture(std::shared_ptr<const vk::Buffer> rgba, int width, int height) {
    if (width <= 0 || height <= 0 || !rgba || rgba->size() < uint64_t(width) * height * 4) return;
    if (width != picture_width_ || height != picture_height_) {
        // The previous frame finished (present waits for its fence), so the old image is free.
        if (picture_) vkDestroyImage(device_, picture_, nullptr);
        if (picture_memory_) vkFreeMemory(device_, picture_memory_, nullptr);
        make_image(ctx_, width, height, VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, picture_,
                   picture_memory_);
        picture_width_ = width;
        picture_height_ = height;
        picture_ready_ = false;
    }
    picture_pending_ = std::move(rgba);
}

Rect Presenter::picture_rect() const {
    Rect v = viewport_;
    if (picture_width_ <= 0 || picture_height_ <= 0 || v.width <= 0 || v.height <= 0) return v;
    const double s = std::min(double(v.width) / picture_width_, double(v.height) / picture_height_);
    Rect r;
    r.width = std::max(1, int(picture_width_ * s + 0.5));
    r.height = std::max(1, int(picture_height_ * s + 0.5));
    r.x = v.x + (v.width - r.width) / 2;
    r.y = v.y + (v.height - r.height) / 2;
    return r;
}

VkCommandBuffer Presenter::begin_once() {
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    PG_VK(vkResetCommandBuffer(cmd_, 0));
    PG_VK(vkBeginCommandBuffer(cmd_, &bi));
    return cmd_;
}

void Presenter::end_once(VkCommandBuffer cmd) {
    PG_VK(vkEndCommandBuffer(cmd));
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cmd;
    {
        std::lock_guard lock(ctx_.queue_mutex());
        vk::check(ctx_.queue_submit(si, fence_), "vkQueueSubmit");
    }
    PG_VK(vkWaitForFences(device_, 1, &fence_, VK_TRUE, UINT64_MAX));
    PG_VK(vkResetFences(device_, 1, &fence_));
}

bool Presenter::present_impl(int width, int height, UiRecorder& ui, bool capture) {
    if (width <= 0 || height <= 0) return false;
    if (width != swap_width_ || height != swap_height_) {
        {
            std::lock_guard lock(ctx_.queue_mutex());
            vkQueueWaitIdle(ctx_.queue());
        }
        create_swapchain(width, height);
    }
    uint32_t index = 0;
    VkResult r = vkAcquireNextImageKHR(device_, swapchain_, UINT64_MAX, acquired_, VK_NULL_HANDLE, &index);
    if (r == VK_ERROR_OUT_OF_DATE_KHR) {
        swap_width_ = 0;  // rebuilt on the next frame
        return true;
    }
    if (r != VK_SUBOPTIMAL_KHR) PG_VK(r);

    VkCommandBuffer cmd = begin_once();
    if (picture_pending_) {
        VkMemoryBarrier written{VK_STRUCTURE_TYPE_MEMORY_BARRIER};  // by the overlay pass, in an earlier submission
        written.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
        written.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &written, 0,
                             nullptr, 0, nullptr);
        image_barrier(cmd, picture_, picture_ready_ ? VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL : VK_IMAGE_LAYOUT_UNDEFINED,
                      VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_ACCESS_TRANSFER_READ_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                      VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT);
        VkBufferImageCopy copy{};
        copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        copy.imageExtent = {uint32_t(picture_width_), uint32_t(picture_height_), 1};
        vkCmdCopyBufferToImage(cmd, picture_pending_->handle(), picture_, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
        image_barrier(cmd, picture_, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                      VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                      VK_PIPELINE_STAGE_TRANSFER_BIT);
        picture_ready_ = true;
    }
    image_barrier(cmd, target_, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                  VK_ACCESS_TRANSFER_READ_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                  VK_PIPELINE_STAGE_TRANSFER_BIT);
    VkClearColorValue background{{0.11f, 0.11f, 0.13f, 1.0f}};
    VkImageSubresourceRange all{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdClearColorImage(cmd, target_, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &background, 1, &all);
    if (picture_ready_) {
        VkImageBlit region = blit_region(picture_width_, picture_height_, picture_rect());
        VkMemoryBarrier clear_done{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        clear_done.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        clear_done.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &clear_done, 0,
                             nullptr, 0, nullptr);
        vkCmdBlitImage(cmd, picture_, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, target_, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                       1, &region, VK_FILTER_LINEAR);
    }
    image_barrier(cmd, target_, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                  VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
                  VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT);
    VkRenderPassBeginInfo rb{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    rb.renderPass = render_pass_;
    rb.framebuffer = framebuffer_;
    rb.renderArea.extent = {uint32_t(target_width_), uint32_t(target_height_)};
    vkCmdBeginRenderPass(cmd, &rb, VK_SUBPASS_CONTENTS_INLINE);
    ui.record(cmd);
    vkCmdEndRenderPass(cmd);  // the target is now TRANSFER_SRC_OPTIMAL
    if (capture) {
        VkBufferImageCopy copy{};
        copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        copy.imageExtent = {uint32_t(target_width_), uint32_t(target_height_), 1};
        vkCmdCopyImageToBuffer(cmd, target_, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback_.handle(), 1, &copy);
        VkMemoryBarrier to_host{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        to_host.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        to_host.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &to_host, 0, nullptr,
                             0, nullptr);
    }
    VkImage swap = swap_images_[index];
    image_barrier(cmd, swap, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0,
                  VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT);
    VkImageBlit whole = blit_region(target_width_, target_height_, {0, 0, swap_width_, swap_height_});
    vkCmdBlitImage(cmd, target_, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, swap, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                   &whole, VK_FILTER_NEAREST);
    image_barrier(cmd, swap, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR,
                  VK_ACCESS_TRANSFER_WRITE_BIT, 0, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT);
    PG_VK(vkEndCommandBuffer(cmd));

    VkPipelineStageFlags wait_stage = VK_PIPELINE_STAGE_TRANSFER_BIT;
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.waitSemaphoreCount = 1;
    si.pWaitSemaphores = &acquired_;
    si.pWaitDstStageMask = &wait_stage;
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cmd;
    si.signalSemaphoreCount = 1;
    si.pSignalSemaphores = &rendered_;
    VkPresentInfoKHR pi{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
    pi.waitSemaphoreCount = 1;
    pi.pWaitSemaphores = &rendered_;
    pi.swapchainCount = 1;
    pi.pSwapchains = &swapchain_;
    pi.pImageIndices = &index;
    VkResult pr;
    {
        std::lock_guard lock(ctx_.queue_mutex());
        vk::check(ctx_.queue_submit(si, fence_), "vkQueueSubmit");
        pr = vkQueuePresentKHR(ctx_.queue(), &pi);
    }
    PG_VK(vkWaitForFences(device_, 1, &fence_, VK_TRUE, UINT64_MAX));
    PG_VK(vkResetFences(device_, 1, &fence_));
    picture_pending_.reset();  // copied: the frame engine may write it again
    if (pr == VK_ERROR_OUT_OF_DATE_KHR || pr == VK_SUBOPTIMAL_KHR) swap_width_ = 0;
    else PG_VK(pr);
    if (capture) {
        const uint8_t* px = readback_.as<uint8_t>();
        captured_.assign(px, px + size_t(target_width_) * target_height_ * 4);
    }
    return true;
}

}  // namespace pg::viewer

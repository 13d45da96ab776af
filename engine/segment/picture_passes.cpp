#include "engine/segment/picture_passes.h"

#include "shaders/segment/picture_shared.h"

namespace pg::seg {

namespace {
uint32_t groups(int pixels) { return vk::ceil_div(uint32_t(pixels), gpu::kPictureSide); }
}  // namespace

PicturePasses::PicturePasses(vk::Context& ctx) : none_(ctx, 16, vk::MemoryUse::Device, "picture: no labels") {}

void PicturePasses::overlay(vk::CommandList& cmd, const vk::Buffer& render, const vk::Buffer* labels,
                            const vk::Buffer* palette, uint32_t palette_size, int width, int height,
                            vk::Buffer& picture) {
    const bool labelled = labels && palette && palette_size > 0;
    const gpu::OverlayPush push{uint32_t(width), uint32_t(height), labelled ? palette_size : 0u, labelled ? 1u : 0u};
    const VkDeviceSize pixels = VkDeviceSize(width) * VkDeviceSize(height);
    picture.ensure(pixels * 4);
    cmd.dispatch_2d("segment/overlay",
                    {vk::BufferRange(render, 0, pixels * 16), labelled ? *labels : none_, labelled ? *palette : none_,
                     vk::BufferRange(picture, 0, pixels * 4)},
                    push, groups(width), groups(height));
}

void PicturePasses::objects(vk::CommandList& cmd, const render::Renderer& rendered, const vk::Buffer& labels,
                            vk::Buffer& objects) {
    const int w = rendered.width(), h = rendered.height();
    const VkDeviceSize pixels = VkDeviceSize(w) * VkDeviceSize(h);
    objects.ensure(pixels * 4);
    const gpu::PixelObjectsPush push{uint32_t(w), uint32_t(h), 0, 0};
    // Whole labels buffer: the shader takes the Gaussian count from its length.
    cmd.dispatch_2d("segment/pixel_objects",
                    {vk::BufferRange(rendered.aux_buffer(), 0, pixels * 16), labels,
                     vk::BufferRange(objects, 0, pixels * 4)},
                    push, groups(w), groups(h));
}

}  // namespace pg::seg

#pragma once
// The passes that turn a render and its labels into what a viewer shows, on the GPU, so a
// picture reaches the screen without a trip through the host: the overlay of
// ViewMask::overlay as RGBA8 (shaders/segment/overlay.comp), and the object under each pixel
// for picking (shaders/segment/pixel_objects.comp).
#include <cstdint>

#include "engine/render/renderer.h"
#include "engine/vk/buffer.h"
#include "engine/vk/commands.h"

namespace pg::seg {

class PicturePasses {
public:
    explicit PicturePasses(vk::Context& ctx);

    // `render`: vec4 per pixel. `labels`: uint32 per pixel (0: none), or null for the render
    // alone; `palette`: rgb per label, a < 0 for a hidden object, whose pixels count as
    // unlabelled; labels at or past `palette_size` count as unlabelled too. `picture` is grown
    // to width * height uint32 (RGBA8, red in the low byte).
    void overlay(vk::CommandList& cmd, const vk::Buffer& render, const vk::Buffer* labels, const vk::Buffer* palette,
                 uint32_t palette_size, int width, int height, vk::Buffer& picture);
    // Per pixel of the frame `rendered` rendered last: the int32 label (`labels`: one per
    // Gaussian) of the Gaussian at which it reached tau, else 0. `objects` is grown to fit.
    void objects(vk::CommandList& cmd, const render::Renderer& rendered, const vk::Buffer& labels, vk::Buffer& objects);

private:
    vk::Buffer none_;  // bound in place of absent labels and palette; never read
};

}  // namespace pg::seg

#include "engine/segment/label_raster.h"

#include <stdexcept>

#include "engine/vk/context.h"

namespace pg::seg {

const char* label_mode_name(LabelMode mode) { return mode == LabelMode::Paper ? "paper" : "occlusion"; }

LabelMode parse_label_mode(const std::string& name) {
    if (name == "paper") return LabelMode::Paper;
    if (name == "occlusion") return LabelMode::Occlusion;
    throw std::invalid_argument("unknown label mode '" + name + "' (expected paper or occlusion)");
}

LabelRasterizer::LabelRasterizer(vk::Context& ctx) : ctx_(ctx), cmd_(ctx) {}

void LabelRasterizer::rasterize(vk::CommandList& cmd, const render::Renderer& renderer,
                                const vk::Buffer& gaussian_labels, vk::Buffer& label_image, LabelMode mode) {
    if (renderer.width() <= 0 || renderer.height() <= 0 || !renderer.tile_ranges().valid())
        throw std::logic_error("label rasterization: the renderer has not rendered a frame yet");
    if (renderer.streamed())
        throw std::runtime_error("label rasterization of a streamed scene (larger than one binding or the memory "
                                 "cap) is not supported yet");
    if (!gaussian_labels.valid() || gaussian_labels.size() < 4)
        throw std::invalid_argument("label rasterization: the Gaussian label buffer is empty");
    const VkDeviceSize bytes = VkDeviceSize(renderer.width()) * VkDeviceSize(renderer.height()) * 4;
    if (!label_image.valid())
        label_image = vk::Buffer(ctx_, bytes, vk::MemoryUse::Device, "label image");
    else
        label_image.ensure(bytes);
    const char* shader = mode == LabelMode::Paper ? "segment/label_paper" : "segment/label_occlusion";
    // Whole ranges: the shader reads the label count from the buffer's length.
    cmd.dispatch_2d(shader,
                    {renderer.frame_buffer(), renderer.splat_buffer(), renderer.tile_values(), renderer.tile_ranges(),
                     gaussian_labels, vk::BufferRange(label_image, 0, bytes)},
                    renderer.tiles_x(), renderer.tiles_y());
}

std::vector<uint32_t> LabelRasterizer::rasterize_and_read(const render::Renderer& renderer,
                                                          const vk::Buffer& gaussian_labels, LabelMode mode) {
    cmd_.begin_pass(std::string("labels ") + label_mode_name(mode));
    rasterize(cmd_, renderer, gaussian_labels, image_, mode);
    cmd_.end_pass();
    cmd_.submit_and_wait();
    last_ms_ = cmd_.total_ms();
    return vk::download_vector<uint32_t>(ctx_, image_, size_t(renderer.width()) * size_t(renderer.height()));
}

}  // namespace pg::seg

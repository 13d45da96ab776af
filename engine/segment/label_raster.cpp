#include "engine/segment/label_raster.h"

#include <algorithm>
#include <stdexcept>

#include "engine/vk/context.h"
#include "shaders/render/render_shared.h"

namespace pg::seg {

const char* label_mode_name(LabelMode mode) { return mode == LabelMode::Paper ? "paper" : "occlusion"; }

LabelMode parse_label_mode(const std::string& name) {
    if (name == "paper") return LabelMode::Paper;
    if (name == "occlusion") return LabelMode::Occlusion;
    throw std::invalid_argument("unknown label mode '" + name + "' (expected paper or occlusion)");
}

LabelRasterizer::LabelRasterizer(vk::Context& ctx)
    : ctx_(ctx),
      cmd_(ctx),
      none_(ctx, 16, vk::MemoryUse::Device, "no label carry"),
      slab_labels_(ctx, 16, vk::MemoryUse::Device, "slab labels"),
      carry_{vk::Buffer(ctx, 16, vk::MemoryUse::Device, "label carry"), vk::Buffer(ctx, 16, vk::MemoryUse::Device, "label carry")},
      window_carry_{vk::Buffer(ctx, 16, vk::MemoryUse::Device, "label window carry"),
                    vk::Buffer(ctx, 16, vk::MemoryUse::Device, "label window carry")} {}

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
    // Whole ranges: the shader reads the label count from the buffer's length.
    record(cmd, renderer, gaussian_labels, vk::BufferRange(label_image, 0, bytes), none_, none_,
           renderer.tile_windows(), mode);
}

void LabelRasterizer::record(vk::CommandList& cmd, const render::Renderer& renderer, vk::BufferRange labels,
                             vk::BufferRange image, const vk::Buffer& carry_in, const vk::Buffer& carry_out,
                             uint32_t windows, LabelMode mode) {
    if (windows > 1)
        for (auto& w : window_carry_)
            w.ensure(uint64_t(renderer.width()) * uint64_t(renderer.height()) * render::gpu::kLabelCarryWords * 4);
    // One window: the variant without the window carry (faster on lavapipe). The occlusion pass
    // draws a column of two pixels per invocation where the renderer's blend draws columns.
    const bool column = renderer.blend_kernel() == render::BlendKernel::Column;
    const char* shader = mode == LabelMode::Paper ? (windows > 1 ? "segment/label_paper_windows" : "segment/label_paper")
                         : column ? (windows > 1 ? "segment/label_occlusion_windows_rows2" : "segment/label_occlusion_rows2")
                                  : (windows > 1 ? "segment/label_occlusion_windows_rows1" : "segment/label_occlusion_rows1");
    for (uint32_t w = 0; w < windows; ++w)
        cmd.dispatch_2d(shader,
                        {renderer.frame_buffer(), renderer.splat_buffer(), renderer.tile_values(), renderer.tile_ranges(),
                         labels, image, carry_in, carry_out, windows > 1 ? window_carry_[w % 2] : none_,
                         windows > 1 ? window_carry_[(w + 1) % 2] : none_},
                        render::gpu::TileWindowPush{{w, windows, 0, 0}}, renderer.tiles_x(), renderer.tiles_y());
}

void LabelRasterizer::rasterize_slab(vk::CommandList& cmd, const render::Renderer& renderer,
                                     const render::SlabPass& slab, const vk::Buffer& gaussian_labels,
                                     vk::Buffer& label_image, LabelMode mode) {
    if (!gaussian_labels.valid() || gaussian_labels.size() < 4)
        throw std::invalid_argument("label rasterization: the Gaussian label buffer is empty");
    const uint64_t pixels = uint64_t(renderer.width()) * uint64_t(renderer.height());
    const VkDeviceSize bytes = pixels * 4;
    if (!label_image.valid()) label_image = vk::Buffer(ctx_, bytes, vk::MemoryUse::Device, "label image");
    else label_image.ensure(bytes);
    const vk::Buffer* labels = &gaussian_labels;
    if (slab.ids) {
        // The slab's labels in slab order; exactly `size` of them, so the shader's length check holds.
        slab_labels_.ensure(std::max<uint64_t>(uint64_t(slab.size) * 4, 16));
        cmd.dispatch("render/gather_labels", {*slab.ids, gaussian_labels, slab_labels_},
                     render::gpu::GatherPush{{slab.size, 0, 0, 0}}, vk::ceil_div(slab.size, 256));
        labels = &slab_labels_;
    }
    for (auto& c : carry_) c.ensure(pixels * render::gpu::kLabelCarryWords * 4);
    const vk::BufferRange slab_range(*labels, 0, std::max<uint64_t>(uint64_t(slab.size) * 4, 4));
    record(cmd, renderer, slab.ids ? slab_range : vk::BufferRange(gaussian_labels), vk::BufferRange(label_image, 0, bytes),
           carry_[slab.index % 2], carry_[(slab.index + 1) % 2], slab.windows, mode);
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

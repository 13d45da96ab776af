#pragma once
// Label rasterization: turns per-Gaussian labels into a per-pixel label image for the frame
// the renderer rendered last, walking the same per-tile, front-to-back Gaussian lists the
// renderer's blend pass walked (shaders/segment/label_*.comp).
//
// Labels are uint32 per Gaussian (index as in the GpuScene), 0 = unlabelled; the buffer must
// hold one per Gaussian of the rendered scene (reads past its end yield 0, never a fault).
// The label image is uint32 per pixel, row-major, top row first, in the frame's resolution;
// 0 = no label.
#include <cstdint>
#include <string>
#include <vector>

#include "engine/render/renderer.h"
#include "engine/vk/buffer.h"
#include "engine/vk/commands.h"

namespace pg::seg {

enum class LabelMode {
    // Algorithm 1 of the paper: the label of the first Gaussian (front to back in the pixel's
    // tile list) with label > 0 whose projected centre is within rho^2 <= 4 px^2 of the pixel
    // centre, else 0. The tile list holds the Gaussians whose alpha >= 1/255 support reaches a
    // pixel centre of the tile. No transmittance cut-off: labelled Gaussians behind opaque
    // unlabelled ones still show, as in the paper.
    Paper,
    // The renderer's blending (alpha = min(0.99, o exp(power)), skipped below 1/255, stopped
    // before T < 1e-4); each weight alpha * T goes to its Gaussian's label (unlabelled: 0).
    // The pixel takes the label of largest weight (ties: the smaller label) when its opacity
    // 1 - T >= 0.5, else 0. Up to 8 labels > 0 per pixel are tracked; a ninth replaces the one
    // of smallest weight (ties: the larger label), whose weight is dropped.
    Occlusion,
};

const char* label_mode_name(LabelMode mode);
LabelMode parse_label_mode(const std::string& name);  // "paper" | "occlusion"; throws otherwise

class LabelRasterizer {
public:
    explicit LabelRasterizer(vk::Context& ctx);

    // Records the label pass into `cmd` (no submit, no wait). `renderer` must have rendered a
    // frame, whose binning must still be on the device. `label_image` is created or grown to
    // width * height uint32 as needed.
    void rasterize(vk::CommandList& cmd, const render::Renderer& renderer, const vk::Buffer& gaussian_labels,
                   vk::Buffer& label_image, LabelMode mode);

    // The same for one slab of a streamed frame (call it from the frame's SlabHook): the slab's
    // labels are gathered from `gaussian_labels` (scene order), the pixel state passes from
    // slab to slab, and the last slab writes `label_image`.
    void rasterize_slab(vk::CommandList& cmd, const render::Renderer& renderer, const render::SlabPass& slab,
                        const vk::Buffer& gaussian_labels, vk::Buffer& label_image, LabelMode mode);

    // Convenience: uploads nothing, runs rasterize() on an own command list, waits and reads
    // the image back. The pass's GPU time is in last_ms().
    std::vector<uint32_t> rasterize_and_read(const render::Renderer& renderer, const vk::Buffer& gaussian_labels,
                                             LabelMode mode);
    double last_ms() const { return last_ms_; }

private:
    // One dispatch per window of the tile lists, the pixel state passed between them.
    void record(vk::CommandList& cmd, const render::Renderer& renderer, vk::BufferRange labels, vk::BufferRange image,
                const vk::Buffer& carry_in, const vk::Buffer& carry_out, uint32_t windows, LabelMode mode);

    vk::Context& ctx_;
    vk::CommandList cmd_;
    vk::Buffer image_;
    vk::Buffer none_, slab_labels_, carry_[2];  // none_: bound where a pass reads no carry
    vk::Buffer window_carry_[2];
    double last_ms_ = 0.0;
};

}  // namespace pg::seg

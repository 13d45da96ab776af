#pragma once
// Per-view 2D masks from 3D labels: render the view (for the binning and the colours),
// rasterize the labels, refine the mask, all on the GPU; then read the mask back.
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "dataset/camera.h"
#include "engine/render/renderer.h"
#include "engine/segment/label_raster.h"
#include "engine/segment/mask_refine.h"

namespace pg::seg {

struct MaskViewsOptions {
    LabelMode mode = LabelMode::Occlusion;
    bool refine = true;
    render::RenderSettings render;
};

struct ViewMask {
    int width = 0, height = 0;
    std::vector<uint32_t> labels;  // per pixel, row-major
    std::vector<float> rgba;       // the render, for overlays
    std::vector<uint16_t> mask16() const;
    // The render with each object tinted in its colour (rgb in [0, 1]) and outlined; RGB8.
    std::vector<uint8_t> overlay(const std::function<glm::vec3(uint32_t)>& colour = default_colour) const;
    static glm::vec3 default_colour(uint32_t label);
};

class MaskViews {
public:
    MaskViews(vk::Context& ctx, const render::GpuScene& scene, const std::vector<int32_t>& labels);
    // Labels already on the device (uint32 per Gaussian, 0: none), kept by the caller.
    MaskViews(vk::Context& ctx, const render::GpuScene& scene, const vk::Buffer& labels);

    ViewMask render(const data::Camera& camera, const MaskViewsOptions& options, bool read_rgba = true);
    // The mask of the frame `rendered` rendered last (its binning still on the device), left on
    // the device; valid until the next call.
    const vk::Buffer& label_image(const render::Renderer& rendered, const MaskViewsOptions& options);
    // The same for `camera`, rendered here first (options.render applies).
    const vk::Buffer& label_image(const data::Camera& camera, const MaskViewsOptions& options);
    // GPU ms per stage summed over the views rendered so far.
    const std::map<std::string, double>& stage_ms() const { return stage_ms_; }

private:
    // Refines raw_ (the label image just rasterized) when the options ask; runs the recorded passes.
    const vk::Buffer& refined(const render::Renderer& rendered, const MaskViewsOptions& options);
    vk::Context& ctx_;
    const render::GpuScene& scene_;
    render::Renderer renderer_;
    LabelRasterizer rasterizer_;
    MaskRefiner refiner_;
    vk::CommandList cmd_;
    vk::Buffer own_labels_, raw_, refined_;
    const vk::Buffer* labels_;
    std::map<std::string, double> stage_ms_;
};

}  // namespace pg::seg

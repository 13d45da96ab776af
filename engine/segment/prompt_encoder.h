#pragma once
// Cross-modal prompt encoder: a click in a view becomes a 3D anchor on the pixel's ray (see
// LiftRule for where along it), and every Gaussian gets
// positive/negative click weights; the ROI column around the first positive anchor is
// gathered on the GPU.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "dataset/camera.h"
#include "dataset/gaussian_cloud.h"
#include "engine/render/gpu_scene.h"
#include "engine/render/renderer.h"
#include "engine/segment/anchor.h"
#include "engine/segment/pixel_candidates.h"
#include "engine/sort/prefix_sum.h"

namespace pg::seg {

// Lifts pixel (u, v) of `camera` (column, row; the ray goes through the pixel's centre) by
// `rule`: the anchor is the point of the ray at the chosen Gaussian's depth (the dominant
// surface's weighted median Gaussian, or the one at which the opacity reached tau). A pixel that is
// clearly covered (final opacity >= kMinLiftCoverage) but never reaches tau — a translucent
// wall, a blurry edge, a thin part — takes tau x its final opacity under the tau rule: the
// same fraction of what the ray meets.
// Throws InputError naming `what` when the pixel is off the image or (nearly) empty.
// Renders only what may reach the pixel (a window of the view at the camera's own size), as a
// scene of its own picked on the host from scene.cloud() (which must still be alive): a few
// hundred Gaussians whatever the scene's size, so every click renders its own. The renderer
// then holds no frame to pick from (Renderer::forget_scene): render again before pick().
// `bins`: the caller's per-view bins of scene.cloud() (the same answers; a further click in a
// view then costs one bin, not a scan of the scene).
Anchor lift_click(render::Renderer& renderer, const render::GpuScene& scene, const data::Camera& camera, double u,
                  double v, bool positive, const render::RenderSettings& settings, LiftRule rule,
                  const std::string& what, PixelBins* bins = nullptr);

// A click given in 3D: the anchor is the point itself, and the Gaussian of nearest centre
// stands for the surface it hit (a scan of the cloud on the host).
Anchor anchor_at_point(const data::GaussianCloud& cloud, const glm::dvec3& point, bool positive);

struct RoiBox {
    glm::dvec3 centre{0.0}, length_axis{1, 0, 0}, width_axis{0, 0, 1};
    double length = 1.0, width = 1.0;  // full extents along the two horizontal axes
};

// Whether `p` lies in the ROI's column scaled by `factor` about its centre (any height).
bool in_column(const RoiBox& r, const glm::dvec3& p, double factor = 1.0);

// The ROI's Gaussians (ascending indices) and their click weights (positive, negative).
struct EncodedPrompt {
    std::vector<uint32_t> indices;
    std::vector<glm::vec2> weights;
};

class PromptEncoder {
public:
    explicit PromptEncoder(vk::Context& ctx);
    // Records and runs the weights + ROI passes; the host waits once, for the ROI's size.
    // `candidates`: ascending Gaussian ids that hold every one in the ROI column (ColumnIndex),
    // so the passes cost the column, not the scene; null: every Gaussian.
    EncodedPrompt encode(const render::GpuScene& scene, const std::vector<Anchor>& anchors, double sigma,
                         const RoiBox& roi, const std::vector<uint32_t>* candidates = nullptr);
    const std::vector<vk::PassTiming>& timings() const { return timings_; }

private:
    vk::Context& ctx_;
    vk::CommandList cmd_;
    sort::PrefixSum scan_;
    vk::Buffer anchors_, weights_, flags_, offsets_, total_, indices_, roi_weights_;
    vk::Buffer means_window_;  // a streamed scene's centres, a chunk at a time
    std::vector<vk::PassTiming> timings_;
};

}  // namespace pg::seg

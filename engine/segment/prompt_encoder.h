#pragma once
// Cross-modal prompt encoder: a click in a view becomes a 3D anchor (the depth where the
// accumulated opacity first reaches tau along the pixel's ray), and every Gaussian gets
// positive/negative click weights; the ROI column around the first positive anchor is
// gathered on the GPU.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "dataset/camera.h"
#include "engine/render/gpu_scene.h"
#include "engine/render/renderer.h"
#include "engine/sort/prefix_sum.h"

namespace pg::seg {

struct Anchor {
    glm::dvec3 position{0.0};
    bool positive = true;
    int32_t gaussian = -1;  // the Gaussian at which opacity reached tau (-1 for 3D clicks)
    // The pixel's opacity never reached tau, so the anchor is where it reached tau x its final
    // opacity (see lift_click); `coverage` is that final opacity (1 for 3D clicks).
    bool fallback = false;
    float coverage = 1.0f;
};

// A pixel whose final opacity is below this is empty: a click there lifts to nothing.
constexpr float kMinLiftCoverage = 0.5f;

// Lifts pixel (u, v) of `camera` (column, row; the ray goes through the pixel's centre) to the
// depth where the accumulated opacity first reaches tau (the paper's rule). A pixel that is
// clearly covered (final opacity >= kMinLiftCoverage) but never reaches tau — a translucent
// wall, a blurry edge, a thin part — lifts where the opacity reaches tau x its final value:
// the same fraction of what the ray meets, and the view is rendered once more for it.
// Throws InputError naming `what` when the pixel is off the image or (nearly) empty.
// Renders the view at the camera's own size unless `rendered` says the renderer's last frame is
// already this view with these settings; after a fallback the renderer holds another tau.
Anchor lift_click(render::Renderer& renderer, const render::GpuScene& scene, const data::Camera& camera, double u,
                  double v, bool positive, const render::RenderSettings& settings, const std::string& what,
                  bool rendered = false);

struct RoiBox {
    glm::dvec3 centre{0.0}, length_axis{1, 0, 0}, width_axis{0, 0, 1};
    double length = 1.0, width = 1.0;  // full extents along the two horizontal axes
};

// The ROI's Gaussians (ascending indices) and their click weights (positive, negative).
struct EncodedPrompt {
    std::vector<uint32_t> indices;
    std::vector<glm::vec2> weights;
};

class PromptEncoder {
public:
    explicit PromptEncoder(vk::Context& ctx);
    // Records and runs the weights + ROI passes; the host waits once, for the ROI's size.
    EncodedPrompt encode(const render::GpuScene& scene, const std::vector<Anchor>& anchors, double sigma,
                         const RoiBox& roi);
    const std::vector<vk::PassTiming>& timings() const { return timings_; }

private:
    vk::Context& ctx_;
    vk::CommandList cmd_;
    sort::PrefixSum scan_;
    vk::Buffer anchors_, weights_, flags_, offsets_, total_, indices_, roi_weights_;
    std::vector<vk::PassTiming> timings_;
};

}  // namespace pg::seg

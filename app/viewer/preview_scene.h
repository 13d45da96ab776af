#pragma once
// What the viewer draws while the camera moves over a streamed scene: every m-th Gaussian,
// resident on the device, so a moving frame costs one small render instead of every slab.
// Each kept Gaussian is widened by m^(1/4) along every axis, so surfaces with m times fewer
// Gaussians stay closed: sqrt(m) (each covering m times the area) turns a real capture's faint
// halo Gaussians into a glow over everything; m^(1/4) keeps it sharp with few holes (compared
// on the real guitar at m = 8). The full frame comes back when the camera rests.
#include <cstdint>
#include <memory>
#include <vector>

#include "dataset/gaussian_cloud.h"
#include "engine/render/gpu_scene.h"

namespace pg::viewer {

struct PreviewCloud {
    data::GaussianCloud cloud;
    std::vector<uint32_t> ids;  // the scene index of each preview Gaussian
    uint32_t stride = 1;        // m: one Gaussian of every m
};

// At most `count` Gaussians of `cloud`, every m-th from the first (m = ceil(size / count)).
PreviewCloud make_preview_cloud(const data::GaussianCloud& cloud, uint32_t count);

// The scene and its preview on one device within one budget: a streamed scene gives a fifth
// of its slab memory to a resident preview; a resident scene, or one whose preview would hold
// fewer than kMinPreview Gaussians, has none.
struct ViewedScene {
    std::unique_ptr<render::GpuScene> scene;
    std::unique_ptr<PreviewCloud> preview;
    std::unique_ptr<render::GpuScene> preview_scene;
};
inline constexpr uint32_t kMinPreview = 16384;
ViewedScene upload_viewed_scene(vk::Context& ctx, const data::GaussianCloud& cloud, const render::SceneBudget& budget);

}  // namespace pg::viewer

#pragma once
// The render thread's half of the viewer: renders the current view with the 3D labels as
// tints (hidden objects culled) and, when asked, the refined 2D mask of every visible object
// outlined on top, exactly as the exported overlays draw it.
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "dataset/camera.h"
#include "engine/render/renderer.h"
#include "engine/segment/mask_views.h"

namespace pg::viewer {

struct FrameRequest {
    uint64_t id = 0;
    data::Camera camera;
    std::shared_ptr<const std::vector<int32_t>> labels;  // object id per Gaussian (may be null)
    uint64_t labels_version = 0;
    // Per object id: rgb and how strongly the Gaussians take it (0 none, < 0 hidden).
    std::vector<glm::vec4> palette;
    bool mask = false;  // outline the objects' 2D masks
    render::RenderSettings settings;
};

struct FramePicture {
    uint64_t id = 0;
    data::Camera camera;        // what was rendered (its size is the picture's)
    std::vector<uint8_t> rgba;  // RGBA8, row-major
    std::vector<int32_t> object;  // per pixel: the object whose Gaussian made it opaque, 0 for none
    bool mask = false;
    double render_ms = 0, mask_ms = 0;  // GPU time of the splat render and of the mask passes
    double wall_ms = 0;
};

class FrameEngine {
public:
    FrameEngine(vk::Context& ctx, const render::GpuScene& scene);
    FramePicture render(const FrameRequest& request);

private:
    vk::Context& ctx_;
    const render::GpuScene& scene_;
    render::Renderer renderer_;
    vk::Buffer labels_, palette_;
    std::vector<glm::vec4> palette_uploaded_;  // what palette_ holds: an unchanged palette is not re-sent
    uint64_t labels_version_ = ~0ull;
    std::unique_ptr<seg::MaskViews> masks_;
};

}  // namespace pg::viewer

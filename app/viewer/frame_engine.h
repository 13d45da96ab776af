#pragma once
// The render thread's half of the viewer: renders the current view with the 3D labels as
// tints (hidden objects culled), where no object holds a Gaussian its class's tint (label by
// class), and, when asked, the refined 2D mask of every visible object outlined on top,
// exactly as the exported overlays draw it. The picture stays on the device:
// the presenter copies it into the window's image.
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "dataset/camera.h"
#include "engine/render/renderer.h"
#include "engine/segment/mask_views.h"
#include "engine/segment/picture_passes.h"

namespace pg::viewer {

struct FrameRequest {
    uint64_t id = 0;
    data::Camera camera;
    std::shared_ptr<const std::vector<int32_t>> labels;  // object id per Gaussian (may be null)
    uint64_t labels_version = 0;
    // Class per Gaussian (may be null: no class tints). Tinted as palette[class_base + class]
    // where no object holds the Gaussian; masks and picking see objects alone.
    std::shared_ptr<const std::vector<int32_t>> classes;
    uint64_t classes_version = 0;
    int class_base = 0;
    // Per object id (and class_base + class): rgb and how strongly the Gaussians take it (0 none, < 0 hidden).
    std::vector<glm::vec4> palette;
    bool mask = false;  // outline the objects' 2D masks
    bool preview = false;  // draw the scene's preview, if it has one (a moving camera)
    render::RenderSettings settings;
};

struct FramePicture {
    uint64_t id = 0;
    data::Camera camera;        // what was rendered (its size is the picture's)
    // On the device, row-major; the engine reuses them once nobody holds them.
    std::shared_ptr<const vk::Buffer> rgba;    // RGBA8, red in the low byte
    std::shared_ptr<const vk::Buffer> object;  // int32 per pixel: the object whose Gaussian made it opaque,
                                               // 0 for none; null while nothing is labelled
    bool mask = false;
    bool preview = false;       // drawn from the preview (no object ids then)
    double render_ms = 0, mask_ms = 0, overlay_ms = 0;  // GPU time of the splat render, mask and overlay passes
    double wall_ms = 0;
};

class FrameEngine {
public:
    // `preview` (may be null): what a request with `preview` set draws instead of the scene.
    FrameEngine(vk::Context& ctx, const render::GpuScene& scene, const render::GpuScene* preview = nullptr,
                const std::vector<uint32_t>* preview_ids = nullptr);
    FramePicture render(const FrameRequest& request);

private:
    struct Pixels {
        vk::Buffer rgba, object;
    };
    std::shared_ptr<Pixels> free_pixels();
    // The request's palette (uploaded when it changed) over `labels`; no style without a palette.
    render::RenderStyle tints(const FrameRequest& request, const vk::Buffer& labels);

    vk::Context& ctx_;
    const render::GpuScene& scene_;
    const render::GpuScene* preview_;
    const std::vector<uint32_t>* preview_ids_;  // the scene index of each preview Gaussian
    render::Renderer renderer_;
    vk::CommandList cmd_;
    seg::PicturePasses passes_;
    std::vector<std::shared_ptr<Pixels>> pixels_;
    vk::Buffer labels_, palette_, preview_labels_;
    std::vector<glm::vec4> palette_uploaded_;  // what palette_ holds: an unchanged palette is not re-sent
    uint64_t labels_version_ = ~0ull;
    std::unique_ptr<seg::MaskViews> masks_;
    // What the style tints by when classes are shown: object ids, else class_base + class.
    struct TintKey {
        uint64_t labels = ~0ull, classes = ~0ull;
        int base = -1;
        bool operator==(const TintKey&) const = default;
    };
    vk::Buffer tint_labels_;
    TintKey tint_key_, preview_key_;
};

}  // namespace pg::viewer

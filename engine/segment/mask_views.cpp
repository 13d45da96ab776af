#include "engine/segment/mask_views.h"

#include <algorithm>
#include <cmath>

#include "dataset/report/palette.h"
#include "shaders/segment/picture_shared.h"

namespace pg::seg {

std::vector<uint16_t> ViewMask::mask16() const {
    std::vector<uint16_t> m(labels.size());
    for (size_t i = 0; i < labels.size(); ++i) m[i] = uint16_t(std::min<uint32_t>(labels[i], 65535u));
    return m;
}

glm::vec3 ViewMask::default_colour(uint32_t label) {
    return glm::vec3(data::report::mask_colour(uint16_t(std::min<uint32_t>(label, 65535u)))) / 255.0f;
}

std::vector<uint8_t> ViewMask::overlay(const std::function<glm::vec3(uint32_t)>& colour) const {
    std::vector<uint8_t> px(size_t(width) * height * 3);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            size_t p = size_t(y) * width + x;
            uint32_t l = labels[p];
            glm::vec3 rgb(rgba[p * 4], rgba[p * 4 + 1], rgba[p * 4 + 2]);
            rgb = glm::clamp(rgb, 0.0f, 1.0f);
            if (l != 0) {
                const glm::vec3 c = colour(l);
                bool edge = (x > 0 && labels[p - 1] != l) || (x + 1 < width && labels[p + 1] != l) ||
                            (y > 0 && labels[p - width] != l) || (y + 1 < height && labels[p + width] != l);
                rgb = edge ? c : gpu::kOverlayRender * rgb + gpu::kOverlayColour * c;
            }
            for (int c = 0; c < 3; ++c) px[p * 3 + c] = uint8_t(std::lround(rgb[c] * 255.0f));
        }
    return px;
}

MaskViews::MaskViews(vk::Context& ctx, const render::GpuScene& scene, const vk::Buffer& labels)
    : ctx_(ctx),
      scene_(scene),
      renderer_(ctx),
      rasterizer_(ctx),
      refiner_(ctx),
      cmd_(ctx),
      raw_(ctx, 0, vk::MemoryUse::Device, "label image"),
      refined_(ctx, 0, vk::MemoryUse::Device, "refined label image"),
      labels_(&labels) {}

MaskViews::MaskViews(vk::Context& ctx, const render::GpuScene& scene, const std::vector<int32_t>& labels)
    : MaskViews(ctx, scene, own_labels_) {
    std::vector<uint32_t> l(labels.size());
    for (size_t i = 0; i < labels.size(); ++i) l[i] = uint32_t(std::max(0, labels[i]));
    own_labels_ = vk::upload_vector(ctx, l, "gaussian labels");
}

const vk::Buffer& MaskViews::label_image(const render::Renderer& rendered, const MaskViewsOptions& o) {
    cmd_.begin_pass("label raster");
    rasterizer_.rasterize(cmd_, rendered, *labels_, raw_, o.mode);
    return refined(rendered, o);
}

const vk::Buffer& MaskViews::refined(const render::Renderer& rendered, const MaskViewsOptions& o) {
    const int w = rendered.width(), h = rendered.height();
    const vk::Buffer* result = &raw_;
    if (o.refine) {
        cmd_.begin_pass("refine");
        RefineOptions ro;
        // The radii are in pixels of a 640-wide image; larger images close larger gaps.
        int s = std::max(1, int(std::lround(w / 640.0)));
        ro.closing_radii = {1 * s, 2 * s, 3 * s};
        refined_.ensure(uint64_t(w) * h * 4);
        refiner_.refine(cmd_, raw_, refined_, w, h, ro);
        result = &refined_;
    }
    cmd_.end_pass();
    cmd_.submit_and_wait();
    for (auto& t : cmd_.timings()) stage_ms_[t.name] += t.ms;
    return *result;
}

const vk::Buffer& MaskViews::label_image(const data::Camera& camera, const MaskViewsOptions& o) {
    if (scene_.streamed()) {
        // Each slab's labels are rasterized while its tile lists are on the device.
        renderer_.render(scene_, camera, o.render, nullptr, [&](vk::CommandList& cmd, const render::SlabPass& slab) {
            cmd.begin_pass("label raster");
            rasterizer_.rasterize_slab(cmd, renderer_, slab, *labels_, raw_, o.mode);
        });
        for (auto& t : renderer_.timings()) stage_ms_[t.name == "label raster" ? t.name : "render"] += t.ms;
        return refined(renderer_, o);
    }
    renderer_.render(scene_, camera, o.render);
    for (auto& t : renderer_.timings()) stage_ms_["render"] += t.ms;
    return label_image(renderer_, o);
}

ViewMask MaskViews::render(const data::Camera& camera, const MaskViewsOptions& o, bool read_rgba) {
    const vk::Buffer& labels = label_image(camera, o);
    const int w = renderer_.width(), h = renderer_.height();
    ViewMask m;
    m.width = w;
    m.height = h;
    m.labels = vk::download_vector<uint32_t>(ctx_, labels, size_t(w) * h);
    if (read_rgba) m.rgba = vk::download_vector<float>(ctx_, renderer_.image_buffer(), size_t(w) * h * 4);
    return m;
}

}  // namespace pg::seg

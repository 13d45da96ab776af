#include "app/viewer/frame_engine.h"

#include <chrono>

namespace pg::viewer {

FrameEngine::FrameEngine(vk::Context& ctx, const render::GpuScene& scene)
    : ctx_(ctx), scene_(scene), renderer_(ctx), palette_(ctx, 16, vk::MemoryUse::Device, "viewer palette") {}

FramePicture FrameEngine::render(const FrameRequest& rq) {
    const auto t0 = std::chrono::steady_clock::now();
    FramePicture out;
    out.id = rq.id;
    out.camera = rq.camera;
    const bool labelled = rq.labels && rq.labels->size() == scene_.size();
    if (labelled && rq.labels_version != labels_version_) {
        labels_ = vk::upload_vector(ctx_, *rq.labels, "viewer labels");
        masks_ = std::make_unique<seg::MaskViews>(ctx_, scene_, *rq.labels);
        labels_version_ = rq.labels_version;
    }
    render::RenderStyle style;
    if (labelled && !rq.palette.empty()) {
        if (rq.palette != palette_uploaded_) {  // on a discrete GPU each upload is a staged copy and a wait
            palette_.ensure(rq.palette.size() * sizeof(glm::vec4));
            vk::upload(ctx_, palette_, rq.palette.data(), rq.palette.size() * sizeof(glm::vec4));
            palette_uploaded_ = rq.palette;
        }
        style.labels = &labels_;
        style.palette = &palette_;
        style.palette_size = uint32_t(rq.palette.size());
    }
    renderer_.render(scene_, rq.camera, rq.settings, style.labels ? &style : nullptr);
    for (auto& t : renderer_.timings()) out.render_ms += t.ms;
    const int w = renderer_.width(), h = renderer_.height();
    seg::ViewMask view;
    view.width = w;
    view.height = h;
    view.rgba = vk::download_vector<float>(ctx_, renderer_.image_buffer(), size_t(w) * h * 4);
    view.labels.assign(size_t(w) * h, 0);
    if (labelled) {  // what is under each pixel, for picking objects by clicking them
        const auto aux = vk::download_vector<glm::uvec4>(ctx_, renderer_.aux_buffer(), size_t(w) * h);
        out.object.resize(aux.size());
        for (size_t p = 0; p < aux.size(); ++p)
            out.object[p] = aux[p].z < rq.labels->size() ? (*rq.labels)[aux[p].z] : 0;
    }
    if (rq.mask && labelled && masks_) {
        seg::MaskViewsOptions mo;
        mo.render = rq.settings;
        const auto before = masks_->stage_ms();
        view.labels = masks_->render(rq.camera, mo, false).labels;
        for (auto& [name, ms] : masks_->stage_ms()) out.mask_ms += ms - (before.count(name) ? before.at(name) : 0.0);
        for (auto& l : view.labels)  // hidden objects get no outline
            if (l < rq.palette.size() && rq.palette[l].a < 0) l = 0;
        out.mask = true;
    }
    const auto colour = [&](uint32_t l) {
        return l < rq.palette.size() ? glm::vec3(rq.palette[l]) : seg::ViewMask::default_colour(l);
    };
    const std::vector<uint8_t> rgb = view.overlay(colour);
    out.rgba.resize(size_t(w) * h * 4);
    for (size_t p = 0; p < size_t(w) * h; ++p) {
        for (int c = 0; c < 3; ++c) out.rgba[4 * p + c] = rgb[3 * p + c];
        out.rgba[4 * p + 3] = 255;
    }
    out.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return out;
}

}  // namespace pg::viewer

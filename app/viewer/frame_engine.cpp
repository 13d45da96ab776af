#include "app/viewer/frame_engine.h"

#include <algorithm>
#include <atomic>
#include <chrono>

namespace pg::viewer {

FrameEngine::FrameEngine(vk::Context& ctx, const render::GpuScene& scene, const render::GpuScene* preview,
                         const std::vector<uint32_t>* preview_ids)
    : ctx_(ctx),
      scene_(scene),
      preview_(preview && preview_ids ? preview : nullptr),
      preview_ids_(preview_ids),
      renderer_(ctx),
      cmd_(ctx),
      passes_(ctx),
      palette_(ctx, 16, vk::MemoryUse::Device, "viewer palette") {}

std::shared_ptr<FrameEngine::Pixels> FrameEngine::free_pixels() {
    for (auto& p : pixels_)
        if (p.use_count() == 1) {
            // Let go of on the main thread once the presenter's copy finished: see that first.
            std::atomic_thread_fence(std::memory_order_acquire);
            return p;
        }
    pixels_.push_back(std::make_shared<Pixels>(Pixels{vk::Buffer(ctx_, 4, vk::MemoryUse::Device, "viewer picture"),
                                                      vk::Buffer(ctx_, 4, vk::MemoryUse::Device, "viewer objects")}));
    return pixels_.back();
}

render::RenderStyle FrameEngine::tints(const FrameRequest& rq, const vk::Buffer& labels) {
    render::RenderStyle style;
    if (rq.palette.empty()) return style;
    if (rq.palette != palette_uploaded_) {  // on a discrete GPU each upload is a staged copy and a wait
        palette_.ensure(rq.palette.size() * sizeof(glm::vec4));
        vk::upload(ctx_, palette_, rq.palette.data(), rq.palette.size() * sizeof(glm::vec4));
        palette_uploaded_ = rq.palette;
    }
    style.labels = &labels;
    style.palette = &palette_;
    style.palette_size = uint32_t(rq.palette.size());
    return style;
}

FramePicture FrameEngine::render(const FrameRequest& rq) {
    const auto t0 = std::chrono::steady_clock::now();
    FramePicture out;
    out.id = rq.id;
    out.camera = rq.camera;
    out.preview = rq.preview && preview_;
    const bool labelled = rq.labels && rq.labels->size() == scene_.size();
    const bool classed = rq.classes && rq.classes->size() == scene_.size();
    if (labelled && !out.preview && rq.labels_version != labels_version_) {
        labels_ = vk::upload_vector(ctx_, *rq.labels, "viewer labels");
        // One upload for both: object ids are >= 0, so the style's int32 and the mask's uint32 agree.
        masks_ = std::make_unique<seg::MaskViews>(ctx_, scene_, labels_);
        labels_version_ = rq.labels_version;
    }
    // The style's label per Gaussian: its object, else (classes shown) class_base + its class.
    const TintKey key{labelled ? rq.labels_version : 0, classed ? rq.classes_version : 0, classed ? rq.class_base : 0};
    auto tint_label = [&](size_t g) {
        const int32_t object = labelled ? (*rq.labels)[g] : 0;
        const int32_t c = classed ? (*rq.classes)[g] : 0;
        return object != 0 || c <= 0 ? object : rq.class_base + c;
    };
    if (classed && !out.preview && key != tint_key_) {
        std::vector<int32_t> tint(scene_.size());
        for (size_t g = 0; g < tint.size(); ++g) tint[g] = tint_label(g);
        tint_labels_ = vk::upload_vector(ctx_, tint, "viewer tint labels");
        tint_key_ = key;
    }
    if ((labelled || classed) && out.preview && key != preview_key_) {
        std::vector<int32_t> sub(preview_ids_->size());
        for (size_t i = 0; i < sub.size(); ++i) sub[i] = tint_label((*preview_ids_)[i]);
        preview_labels_ = vk::upload_vector(ctx_, sub, "viewer preview labels");
        preview_key_ = key;
    }
    const vk::Buffer& styled = out.preview ? preview_labels_ : classed ? tint_labels_ : labels_;
    const render::RenderStyle style = labelled || classed ? tints(rq, styled) : render::RenderStyle{};
    renderer_.render(out.preview ? *preview_ : scene_, rq.camera, rq.settings, style.labels ? &style : nullptr);
    for (auto& t : renderer_.timings()) out.render_ms += t.ms;
    const int w = renderer_.width(), h = renderer_.height();
    const vk::Buffer* mask = nullptr;
    if (rq.mask && labelled && masks_ && !out.preview) {
        seg::MaskViewsOptions mo;
        mo.render = rq.settings;
        const auto before = masks_->stage_ms();
        // Hidden Gaussians leave the frame's tile lists; the mask, as exported, sees every Gaussian, so
        // it then needs a render of its own. Tints alone bin the same: the frame's lists serve, unless
        // the scene is streamed (only the last slab's lists are left; the mask is rasterized per slab).
        const bool hides = std::any_of(rq.palette.begin(), rq.palette.end(), [](const glm::vec4& p) { return p.a < 0; });
        mask = hides || scene_.streamed() ? &masks_->label_image(rq.camera, mo) : &masks_->label_image(renderer_, mo);
        for (auto& [name, ms] : masks_->stage_ms()) out.mask_ms += ms - (before.count(name) ? before.at(name) : 0.0);
        out.mask = true;
    }
    // A preview's pick ids are the preview's Gaussians: it gives no object ids.
    const bool objects = labelled && !out.preview;
    auto pixels = free_pixels();
    cmd_.begin_pass("overlay");
    passes_.overlay(cmd_, renderer_.image_buffer(), mask, style.palette, style.palette_size, w, h, pixels->rgba);
    if (objects) passes_.objects(cmd_, renderer_, labels_, pixels->object);  // for picking objects by pointing at them
    cmd_.end_pass();
    cmd_.submit_and_wait();
    out.overlay_ms = cmd_.total_ms();
    out.rgba = std::shared_ptr<const vk::Buffer>(pixels, &pixels->rgba);
    if (objects) out.object = std::shared_ptr<const vk::Buffer>(pixels, &pixels->object);
    out.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return out;
}

}  // namespace pg::viewer

#include "engine/segment/segmenter.h"

#include <algorithm>
#include <chrono>
#include <limits>

#include "dataset/error.h"
#include "dataset/up_axis.h"
#include "engine/segment/partition.h"

namespace pg::seg {

namespace {
using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }
}  // namespace

Segmenter::Segmenter(vk::Context& ctx, const data::GaussianCloud& cloud, const render::GpuScene& scene,
                     const std::vector<data::Camera>& cameras, Decoder& decoder)
    : ctx_(ctx), cloud_(cloud), scene_(scene), cameras_(cameras), decoder_(decoder), renderer_(ctx), encoder_(ctx) {}

double Segmenter::scale_from_cameras(const glm::dvec3& target) const {
    if (cameras_.empty()) return 1.0;
    std::vector<double> d;
    for (const auto& c : cameras_) d.push_back(glm::length(c.position() - target));
    std::nth_element(d.begin(), d.begin() + long(d.size() / 2), d.end());
    return std::max(1e-6, 0.25 * d[d.size() / 2]);
}

Anchor Segmenter::anchor_for(const data::PromptClick& click, const render::RenderSettings& settings,
                             const std::string& what) {
    if (click.point) {
        // A 3D click: the anchor is the point itself; the nearest Gaussian stands for the surface hit.
        Anchor a;
        a.position = *click.point;
        a.positive = click.positive;
        double best = std::numeric_limits<double>::max();
        for (size_t i = 0; i < cloud_.size(); ++i) {
            double d = glm::length(glm::dvec3(cloud_.mean[i]) - a.position);
            if (d < best) best = d, a.gaussian = int32_t(i);
        }
        return a;
    }
    auto it = std::find_if(cameras_.begin(), cameras_.end(), [&](auto& c) { return c.name == click.view; });
    if (it == cameras_.end()) throw data::InputError(what, "no camera named '" + click.view + "'");
    // A view already in the renderer with the settings that shape the tau-depth needs no second render.
    const std::string key = click.view + "|" + std::to_string(settings.tau) + "|" + std::to_string(settings.near) +
                            "|" + std::to_string(settings.antialiased);
    const bool rendered = rendered_view_ == key;
    rendered_view_.clear();  // if lifting throws, the frame state is unknown
    Anchor a = lift_click(renderer_, scene_, *it, click.u, click.v, click.positive, settings, what, rendered);
    rendered_view_ = key;
    return a;
}

SegmentResult Segmenter::segment(const data::Prompts& prompts, const SegmentOptions& o) {
    SegmentResult result;
    const size_t n = cloud_.size();
    for (size_t k = 0; k < prompts.objects.size(); ++k) {
        const auto& prompt = prompts.objects[k];
        ObjectResult obj;
        obj.id = prompt.id;
        obj.name = prompt.name;

        auto t0 = Clock::now();
        for (size_t c = 0; c < prompt.clicks.size(); ++c)
            obj.anchors.push_back(anchor_for(prompt.clicks[c], o.render,
                                             "prompts: object '" + prompt.name + "' click " + std::to_string(c)));
        result.stage_ms["lift clicks"] += ms_since(t0);

        // The ROI is anchored at the first positive click.
        const Anchor& first = *std::find_if(obj.anchors.begin(), obj.anchors.end(), [](auto& a) { return a.positive; });
        const double scale = o.scale > 0 ? o.scale : scale_from_cameras(first.position);
        obj.sigma = o.sigma > 0 ? o.sigma : 0.4 * scale;
        obj.roi.centre = first.position;
        data::horizontal_axes(o.up, obj.roi.length_axis, obj.roi.width_axis);
        obj.roi.length = o.roi_length > 0 ? o.roi_length : 2.5 * scale;
        obj.roi.width = o.roi_width > 0 ? o.roi_width : 2.5 * scale;

        t0 = Clock::now();
        EncodedPrompt encoded = encoder_.encode(scene_, obj.anchors, obj.sigma, obj.roi);
        result.stage_ms["encode + roi"] += ms_since(t0);
        obj.roi_gaussians = encoded.indices.size();
        if (encoded.indices.empty())
            throw data::InputError("prompts: object '" + prompt.name + "'",
                                   "the ROI around its first positive click holds no Gaussians (try a larger --roi)");

        t0 = Clock::now();
        // Partition positions within the ROI list, then map them back to scene indices.
        std::vector<uint32_t> slots(encoded.indices.size());
        for (uint32_t i = 0; i < slots.size(); ++i) slots[i] = i;
        auto batches = partition_roi(slots, o.max_batch, o.seed + k);
        obj.batches = batches.size();
        result.stage_ms["partition"] += ms_since(t0);

        t0 = Clock::now();
        for (const auto& batch_slots : batches) {
            DecoderBatch batch;
            batch.frame = data::train::RoiFrame::around(first.position, o.up, scale);
            for (auto& a : obj.anchors)
                if (a.positive) batch.click_gaussians.push_back(a.gaussian);
            batch.gaussians.reserve(batch_slots.size());
            for (uint32_t s : batch_slots) {
                uint32_t g = encoded.indices[s];
                batch.gaussians.push_back(g);
                batch.coords.push_back(cloud_.mean[g]);
                batch.features.push_back(encoded.weights[s]);
            }
            auto p = decoder_.predict(batch);
            if (p.size() != batch.gaussians.size())
                throw std::runtime_error("decoder " + decoder_.name() + " returned the wrong number of probabilities");
            // MAP over foreground/background (the paper's fg > bg for two classes).
            for (size_t i = 0; i < p.size(); ++i)
                if (p[i] > 0.5f) obj.claims.push_back({batch.gaussians[i], p[i]});
        }
        result.stage_ms["decode"] += ms_since(t0);
        result.objects.push_back(std::move(obj));
    }
    result.assemble(n);
    return result;
}

void SegmentResult::assemble(size_t gaussian_count) {
    labels.assign(gaussian_count, 0);
    probability.assign(gaussian_count, 0.0f);
    for (const auto& obj : objects)
        for (auto [g, p] : obj.claims)
            if (p > probability[g]) probability[g] = p, labels[g] = obj.id;
    for (auto& obj : objects) obj.labelled = size_t(std::count(labels.begin(), labels.end(), obj.id));
}

bool SegmentResult::remove_object(int id) {
    auto it = std::find_if(objects.begin(), objects.end(), [&](auto& o) { return o.id == id; });
    if (it == objects.end()) return false;
    objects.erase(it);
    assemble(labels.size());
    return true;
}

}  // namespace pg::seg

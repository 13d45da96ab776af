#include "engine/segment/segmenter.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "dataset/error.h"
#include "dataset/up_axis.h"
#include "engine/segment/partition.h"

namespace pg::seg {

namespace {
using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }
}  // namespace

GraphUse parse_graph_use(const std::string& name, const std::string& option) {
    if (name == "ptv3") return GraphUse::None;
    if (name == "graph") return GraphUse::Alone;
    if (name == "ptv3+graph") return GraphUse::Unary;
    throw data::InputError(option, "expected ptv3, graph or ptv3+graph, got '" + name + "'");
}

const char* graph_use_name(GraphUse use) {
    return use == GraphUse::None ? "ptv3" : use == GraphUse::Alone ? "graph" : "ptv3+graph";
}

GraphSolver parse_graph_solver(const std::string& name, const std::string& option) {
    if (name == "walk") return GraphSolver::Walk;
    if (name == "forest") return GraphSolver::Forest;
    if (name == "walk+forest") return GraphSolver::WalkForest;
    throw data::InputError(option, "expected walk, forest or walk+forest, got '" + name + "'");
}

const char* graph_solver_name(GraphSolver solver) {
    return solver == GraphSolver::Walk ? "walk" : solver == GraphSolver::Forest ? "forest" : "walk+forest";
}

size_t ObjectResult::fallback_clicks() const {
    return size_t(std::count_if(anchors.begin(), anchors.end(), [](auto& a) { return a.fallback; }));
}

size_t SegmentResult::failed() const {
    return size_t(std::count_if(objects.begin(), objects.end(), [](auto& o) { return !o.error.empty(); }));
}

Segmenter::Segmenter(vk::Context& ctx, const data::GaussianCloud& cloud, const render::GpuScene& scene,
                     const std::vector<data::Camera>& cameras, Decoder& decoder)
    : ctx_(ctx), cloud_(cloud), scene_(scene), cameras_(cameras), decoder_(&decoder), renderer_(ctx), encoder_(ctx),
      graph_(ctx), coarse_graph_(ctx), walker_(ctx), forest_(ctx) {}

Segmenter::Segmenter(vk::Context& ctx, const data::GaussianCloud& cloud, const render::GpuScene& scene,
                     const std::vector<data::Camera>& cameras)
    : ctx_(ctx), cloud_(cloud), scene_(scene), cameras_(cameras), decoder_(nullptr), renderer_(ctx), encoder_(ctx),
      graph_(ctx), coarse_graph_(ctx), walker_(ctx), forest_(ctx) {}

double Segmenter::scale_from_cameras(const glm::dvec3& target) const {
    if (cameras_.empty()) return 1.0;
    std::vector<double> d;
    for (const auto& c : cameras_) d.push_back(glm::length(c.position() - target));
    std::nth_element(d.begin(), d.begin() + long(d.size() / 2), d.end());
    return std::max(1e-6, 0.25 * d[d.size() / 2]);
}

void Segmenter::index_columns(const glm::dvec3& up) {
    RoiBox roi;
    data::horizontal_axes(up, roi.length_axis, roi.width_axis);
    columns(roi);
}

const ColumnIndex& Segmenter::columns(const RoiBox& roi) {
    if (!columns_ || !columns_->has_axes(roi.length_axis, roi.width_axis))
        columns_.emplace(cloud_, roi.length_axis, roi.width_axis);
    return *columns_;
}

Anchor Segmenter::anchor_for(const data::PromptClick& click, const SegmentOptions& o, const std::string& what) {
    const render::RenderSettings& settings = o.render;
    if (click.point) return anchor_at_point(cloud_, *click.point, click.positive);
    auto it = std::find_if(cameras_.begin(), cameras_.end(), [&](auto& c) { return c.name == click.view; });
    if (it == cameras_.end()) throw data::InputError(what, "no camera named '" + click.view + "'");
    return lift_click(renderer_, scene_, *it, click.u, click.v, click.positive, settings, o.lift, what, &lift_bins_);
}

SegmentResult Segmenter::segment(const data::Prompts& prompts, const SegmentOptions& options, const LiftedClicks& lifted) {
    SegmentOptions o = options;
    o.walk.cancel = o.forest.cancel = o.cancel;
    if (o.graph != GraphUse::Alone && !decoder_)
        throw data::InputError("decoder", std::string(graph_use_name(o.graph)) + " needs a network model");
    SegmentResult result;
    std::vector<std::vector<uint32_t>> rois;
    std::vector<std::vector<float>> probabilities;
    std::vector<ObjectResult*> solved;
    result.objects.reserve(prompts.objects.size());
    for (size_t k = 0; k < prompts.objects.size(); ++k) {
        const auto& prompt = prompts.objects[k];
        ObjectResult& obj = result.objects.emplace_back();
        obj.id = prompt.id;
        obj.name = prompt.name;
        std::vector<uint32_t> roi;
        std::vector<float> p;
        stop_if_cancelled(o.cancel);
        try {
            const bool given = k < lifted.size() && lifted[k].size() == prompt.clicks.size();
            prepare(prompt, k, given ? &lifted[k] : nullptr, o, obj, p, roi, result);
        } catch (const data::InputError& e) {
            if (o.strict) throw;
            obj.error = e.what();
            obj.claims.clear();
            continue;
        }
        if (o.graph == GraphUse::None) {
            // MAP over foreground/background (the paper's fg > bg for two classes).
            for (size_t i = 0; i < roi.size(); ++i)
                if (p[i] > 0.5f) obj.claims.push_back({roi[i], p[i]});
        }
        rois.push_back(std::move(roi));
        probabilities.push_back(std::move(p));
    }
    for (auto& obj : result.objects)
        if (obj.error.empty()) solved.push_back(&obj);
    stop_if_cancelled(o.cancel);
    if (o.graph != GraphUse::None && !solved.empty()) solve_graph(o, solved, rois, probabilities, result);
    result.assemble(cloud_.size());
    return result;
}

void Segmenter::prepare(const data::ObjectPrompt& prompt, size_t index, const std::vector<Anchor>* lifted,
                        const SegmentOptions& o, ObjectResult& obj,
                        std::vector<float>& roi_probability, std::vector<uint32_t>& roi, SegmentResult& result) {
    const std::string what = "prompts: object '" + prompt.name + "'";
    auto t0 = Clock::now();
    if (lifted) obj.anchors = *lifted;
    else
        for (size_t c = 0; c < prompt.clicks.size(); ++c)
            obj.anchors.push_back(anchor_for(prompt.clicks[c], o, what + " click " + std::to_string(c)));
    result.stage_ms["lift clicks"] += ms_since(t0);
    auto first_it = std::find_if(obj.anchors.begin(), obj.anchors.end(), [](auto& a) { return a.positive; });
    if (first_it == obj.anchors.end()) throw data::InputError(what, "has no positive click");

    // The ROI is anchored at the first positive click.
    const Anchor first = *first_it;
    const double scale = o.scale > 0 ? o.scale : scale_from_cameras(first.position);
    obj.sigma = o.sigma > 0 ? o.sigma : 0.4 * scale;
    obj.roi.centre = first.position;
    data::horizontal_axes(o.up, obj.roi.length_axis, obj.roi.width_axis);
    obj.roi.length = o.roi_length > 0 ? o.roi_length : 2.5 * scale;
    obj.roi.width = o.roi_width > 0 ? o.roi_width : 2.5 * scale;

    t0 = Clock::now();
    const auto candidates = columns(obj.roi).candidates(obj.roi.centre, obj.roi.length / 2, obj.roi.width / 2);
    EncodedPrompt encoded;
    if (o.graph == GraphUse::Alone) {
        // The graph alone reads which Gaussians the ROI holds, never the click weights: the column
        // test on the host (a streamed scene's GPU pass gathers and uploads every candidate).
        for (uint32_t g : candidates)
            if (in_column(obj.roi, glm::dvec3(cloud_.mean[g]))) encoded.indices.push_back(g);
    } else {
        encoded = encoder_.encode(scene_, obj.anchors, obj.sigma, obj.roi, &candidates);
    }
    result.stage_ms["encode + roi"] += ms_since(t0);
    obj.roi_gaussians = encoded.indices.size();
    if (encoded.indices.empty())
        throw data::InputError(what, "the ROI around its first positive click holds no Gaussians (try a larger ROI)");
    roi = encoded.indices;
    if (o.graph == GraphUse::Alone) return;

    t0 = Clock::now();
    // Partition positions within the ROI list, then map them back to scene indices.
    std::vector<uint32_t> slots(encoded.indices.size());
    for (uint32_t i = 0; i < slots.size(); ++i) slots[i] = i;
    auto batches = partition_roi(slots, o.max_batch, o.seed + index);
    obj.batches = batches.size();
    result.stage_ms["partition"] += ms_since(t0);

    t0 = Clock::now();
    roi_probability.assign(roi.size(), 0.0f);
    for (const auto& batch_slots : batches) {
        stop_if_cancelled(o.cancel);
        DecoderBatch batch;
        batch.frame = data::RoiFrame::around(first.position, o.up, scale);
        for (auto& a : obj.anchors)
            if (a.positive) batch.click_gaussians.push_back(a.gaussian);
        batch.gaussians.reserve(batch_slots.size());
        for (uint32_t s : batch_slots) {
            uint32_t g = encoded.indices[s];
            batch.gaussians.push_back(g);
            batch.coords.push_back(cloud_.mean[g]);
            batch.features.push_back(encoded.weights[s]);
        }
        auto p = decoder_->predict(batch);
        if (p.size() != batch.gaussians.size())
            throw std::runtime_error("decoder " + decoder_->name() + " returned the wrong number of probabilities");
        for (size_t i = 0; i < p.size(); ++i) roi_probability[batch_slots[i]] = p[i];
    }
    result.stage_ms["decode"] += ms_since(t0);
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

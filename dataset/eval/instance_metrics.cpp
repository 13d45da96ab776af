#include "dataset/eval/instance_metrics.h"

#include <algorithm>
#include <map>
#include <stdexcept>
#include <string>

namespace pg::data::eval {

InstanceScores3d instance_scores_3d(std::span<const int32_t> gt, std::span<const int32_t> pred) {
    int32_t max_id = 0;
    for (int32_t g : gt) max_id = std::max(max_id, g);
    if (max_id > kMaxLabel)
        throw std::invalid_argument("GT instance id " + std::to_string(max_id) + " above " + std::to_string(kMaxLabel));
    LabelOverlap o(size_t(max_id) + 1);
    o.add(gt, pred);

    InstanceScores3d s;
    s.gaussians = o.total;
    s.oa = o.accuracy();
    double sum = 0.0;
    for (int32_t k = 1; k <= max_id; ++k) {
        if (o.gt[size_t(k)] == 0) continue;
        s.objects.push_back({k, *o.iou(k)});
        sum += s.objects.back().iou;
    }
    if (!s.objects.empty()) s.miou = sum / double(s.objects.size());
    return s;
}

InstanceMaskScorer::InstanceMaskScorer(std::vector<int32_t> scene_objects) : scratch_(size_t(kMaxLabel) + 1) {
    for (int32_t k : scene_objects)
        if (k >= 1) objects_.insert(k);
}

void InstanceMaskScorer::add_view(std::string name, std::span<const uint16_t> gt, std::span<const uint16_t> pred) {
    scratch_.add(gt, pred);
    View v{std::move(name), {}};
    // Keep only the ids this view touched (a few), and clear them for the next view.
    for (size_t k = 1; k < scratch_.ids(); ++k) {
        if (scratch_.gt[k] == 0 && scratch_.pred[k] == 0) continue;
        v.ids.push_back({int32_t(k), scratch_.gt[k], scratch_.pred[k], scratch_.both[k]});
        if (scratch_.gt[k] > 0) objects_.insert(int32_t(k));
        scratch_.gt[k] = scratch_.pred[k] = scratch_.both[k] = 0;
    }
    scratch_.gt[0] = scratch_.pred[0] = scratch_.both[0] = 0;
    total_ += scratch_.total;
    agree_ += scratch_.agree;
    scratch_.total = scratch_.agree = 0;
    views_.push_back(std::move(v));
}

InstanceScores2d InstanceMaskScorer::result() const {
    InstanceScores2d s;
    s.pixels = total_;
    if (total_ > 0) s.oa = double(agree_) / double(total_);
    std::map<int32_t, ObjectIou2d> per_object;
    double view_sum = 0.0;
    size_t scored_views = 0;
    for (const View& v : views_) {
        ViewScores vs{v.name, {}, std::nullopt};
        double sum = 0.0;
        for (const IdCounts& c : v.ids) {
            if (!objects_.count(c.id)) continue;  // a predicted id no GT object has
            const double iou = double(c.both) / double(c.gt + c.pred - c.both);
            vs.objects.push_back({c.id, iou});
            sum += iou;
            auto& o = per_object[c.id];
            o.id = c.id;
            o.iou += iou;
            ++o.views;
        }
        if (!vs.objects.empty()) {
            vs.miou = sum / double(vs.objects.size());
            view_sum += *vs.miou;
            ++scored_views;
        }
        s.views.push_back(std::move(vs));
    }
    if (scored_views > 0) s.miou = view_sum / double(scored_views);
    for (auto& [id, o] : per_object) {
        o.iou /= double(o.views);
        s.objects.push_back(o);
    }
    return s;
}

}  // namespace pg::data::eval

#include "dataset/eval/click_metrics.h"

#include <algorithm>

namespace pg::data::eval {

double iou_after_clicks(const ObjectClicks& o, int k) {
    if (o.iou_per_click.empty() || k < 1) return 0.0;
    return o.iou_per_click[std::min(size_t(k), o.iou_per_click.size()) - 1];
}

int clicks_to_reach(const ObjectClicks& o, double threshold) {
    const size_t n = std::min(o.iou_per_click.size(), size_t(kMaxClicks));
    for (size_t c = 0; c < n; ++c)
        if (o.iou_per_click[c] >= threshold) return int(c) + 1;
    return kMaxClicks;
}

std::optional<ClickScores> click_scores(std::span<const ObjectClicks> objects) {
    if (objects.empty()) return std::nullopt;
    ClickScores s;
    s.objects = objects.size();
    for (const auto& o : objects) {
        for (size_t i = 0; i < kIouAtClicks.size(); ++i) s.iou_at[i] += iou_after_clicks(o, kIouAtClicks[i]);
        for (size_t i = 0; i < kNocThresholds.size(); ++i) s.noc[i] += clicks_to_reach(o, kNocThresholds[i]);
    }
    for (auto& v : s.iou_at) v /= double(objects.size());
    for (auto& v : s.noc) v /= double(objects.size());
    return s;
}

}  // namespace pg::data::eval

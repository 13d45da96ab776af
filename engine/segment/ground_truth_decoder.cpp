#include <algorithm>
#include <map>

#include "engine/segment/decoder.h"

namespace pg::seg {

std::vector<float> GroundTruthDecoder::predict(const DecoderBatch& batch) {
    // The target is the most frequent non-zero label near the positive clicks: the Gaussians
    // hit by the clicks and the batch's Gaussians nearest to the anchors (largest positive
    // weight). One hit alone can be a floater or a thin occluder's fringe.
    constexpr size_t kNearest = 16;
    std::map<int32_t, int> votes;
    auto vote = [&](size_t g) {
        if (g < labels_.size() && labels_[g] != 0) ++votes[labels_[g]];
    };
    for (int32_t g : batch.click_gaussians)
        if (g >= 0) vote(size_t(g));
    std::vector<size_t> order(batch.gaussians.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    const size_t k = std::min(kNearest, order.size());
    std::partial_sort(order.begin(), order.begin() + long(k), order.end(), [&](size_t a, size_t b) {
        return batch.features[a].x > batch.features[b].x || (batch.features[a].x == batch.features[b].x && a < b);
    });
    for (size_t j = 0; j < k; ++j)
        if (batch.features[order[j]].x > 0.5f) vote(batch.gaussians[order[j]]);
    int32_t target = 0;
    int best = 0;
    for (auto [label, n] : votes)
        if (n > best) best = n, target = label;
    std::vector<float> p(batch.gaussians.size(), 0.0f);
    if (target == 0) return p;
    for (size_t i = 0; i < p.size(); ++i) p[i] = labels_[batch.gaussians[i]] == target ? 1.0f : 0.0f;
    return p;
}

}  // namespace pg::seg

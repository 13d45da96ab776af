#include <map>

#include "dataset/error.h"
#include "engine/segment/decoder.h"

namespace pg::seg {

std::vector<float> GroundTruthDecoder::predict(const DecoderBatch& batch) {
    // The target is the most frequent non-zero label under the positive clicks.
    std::map<int32_t, int> votes;
    for (int32_t g : batch.click_gaussians)
        if (g >= 0 && size_t(g) < labels_.size() && labels_[size_t(g)] != 0) ++votes[labels_[size_t(g)]];
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

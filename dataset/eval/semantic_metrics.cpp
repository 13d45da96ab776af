#include "dataset/eval/semantic_metrics.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace pg::data::eval {

SemanticScores semantic_scores(const LabelOverlap& counts, std::span<const int32_t> classes) {
    std::vector<int32_t> ids(classes.begin(), classes.end());
    for (size_t k = 0; k < counts.ids(); ++k)
        if (counts.gt[k] > 0 && std::find(ids.begin(), ids.end(), int32_t(k)) == ids.end()) ids.push_back(int32_t(k));

    SemanticScores s;
    s.elements = counts.total;
    s.oa = counts.accuracy();
    double sum = 0.0;
    size_t present = 0;
    for (int32_t c : ids) {
        ClassIou ci{c, counts.iou(c), c >= 0 && size_t(c) < counts.ids() && counts.gt[size_t(c)] > 0};
        if (ci.in_gt) {
            sum += *ci.iou;
            ++present;
        }
        s.classes.push_back(ci);
    }
    if (present > 0) s.miou = sum / double(present);
    return s;
}

SemanticScores semantic_scores_3d(std::span<const int32_t> gt, std::span<const int32_t> pred,
                                  std::span<const int32_t> classes) {
    int32_t max_id = 0;
    for (int32_t g : gt) max_id = std::max(max_id, g);
    if (max_id > kMaxLabel)
        throw std::invalid_argument("GT class id " + std::to_string(max_id) + " above " + std::to_string(kMaxLabel));
    for (int32_t c : classes) max_id = std::max(max_id, std::min(c, kMaxLabel));
    LabelOverlap o(size_t(max_id) + 1);
    o.add(gt, pred);
    return semantic_scores(o, classes);
}

}  // namespace pg::data::eval

#pragma once
// Per-id counts of one (ground truth, prediction) labelling, over Gaussians or pixels: the
// single primitive every IoU and accuracy in pg::data::eval is computed from.
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace pg::data::eval {

// Largest id the metrics track: masks are 16-bit, so 3D labels are held to the same range.
constexpr int32_t kMaxLabel = 65535;

struct LabelOverlap {
    // Indexed by id in [0, ids()). An element whose GT (or predicted) id lies outside that
    // range, e.g. a negative "unlabelled" prediction, is left out of gt (pred) and both;
    // it still counts in total and, if the two ids are equal, in agree.
    std::vector<uint64_t> gt, pred, both;
    uint64_t total = 0;  // elements seen
    uint64_t agree = 0;  // elements whose predicted id equals the GT id (background included)

    explicit LabelOverlap(size_t ids = 0) : gt(ids, 0), pred(ids, 0), both(ids, 0) {}
    size_t ids() const { return gt.size(); }

    // gt_ids and pred_ids are the labels of the same elements; sizes must match.
    void add(std::span<const int32_t> gt_ids, std::span<const int32_t> pred_ids);
    void add(std::span<const uint16_t> gt_ids, std::span<const uint16_t> pred_ids);

    // |P_k ∩ G_k| / |P_k ∪ G_k|, P_k = {predicted id == k}, G_k = {GT id == k};
    // nullopt when both sets are empty (or k is out of range).
    std::optional<double> iou(int32_t k) const;
    // agree / total; nullopt when nothing was seen.
    std::optional<double> accuracy() const;
};

}  // namespace pg::data::eval

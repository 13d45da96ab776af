#pragma once
// Semantic segmentation scores (the paper's Campus table: per-class 3D and 2D IoU, mIoU,
// OA). Counts are pooled over all elements: all Gaussians for 3D, all pixels of all views
// together for 2D (not averaged per view, unlike the instance 2D mIoU).
//   IoU_c = |P_c ∩ G_c| / |P_c ∪ G_c| for class id c (background, id 0, is a class);
//   mIoU  = mean of IoU_c over the classes present in the GT;
//   OA    = fraction of elements whose predicted class equals the GT class.
// A class predicted but absent from the GT is reported with IoU 0 and left out of mIoU.
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "dataset/eval/label_overlap.h"

namespace pg::data::eval {

struct ClassIou {
    int32_t id = 0;
    std::optional<double> iou;  // nullopt if neither the GT nor the prediction has the class
    bool in_gt = false;         // counts toward mIoU
};

struct SemanticScores {
    std::vector<ClassIou> classes;  // the listed classes in order, then other GT classes by id
    std::optional<double> miou;     // nullopt if the GT is empty
    std::optional<double> oa;
    uint64_t elements = 0;
};

SemanticScores semantic_scores(const LabelOverlap& counts, std::span<const int32_t> classes);

// Over Gaussians. GT ids must be <= kMaxLabel (std::invalid_argument otherwise).
SemanticScores semantic_scores_3d(std::span<const int32_t> gt, std::span<const int32_t> pred,
                                  std::span<const int32_t> classes);

}  // namespace pg::data::eval

#pragma once
// Instance segmentation scores: 3D IoU on Gaussians and 2D mIoU / OA on per-view masks,
// the three columns of the paper's tables (3D, 2D, OA). Ids are aligned: predicted id k
// is the prediction for GT instance k; 0 is background. Values are fractions in [0, 1].
//
// 3D, over Gaussian indices i:
//   IoU_k = |P_k ∩ G_k| / |P_k ∪ G_k|, P_k = {i : pred_i == k}, G_k = {i : gt_i == k},
//   for every GT object k >= 1 present in the GT labels; 3D mIoU = mean of IoU_k over them.
//   OA_3d = fraction of Gaussians with pred_i == gt_i (background included).
//
// 2D, over the pixels of each view v:
//   the objects of v are the scene's objects k >= 1 found in v's GT mask or in its
//   prediction (a predicted object absent from the GT view scores 0 there);
//   mIoU_v = mean of IoU_{k,v} over the objects of v;
//   2D mIoU = mean of mIoU_v over the views that have at least one object (the paper
//   averages per view, so small objects weigh as much as large ones within a view);
//   per-object 2D IoU = mean of IoU_{k,v} over the views where k is an object of v;
//   OA = fraction of all pixels of all views whose predicted id equals the GT id.
// The scene's objects are the ids given to the scorer plus every id >= 1 seen in a GT mask.
// Predicted ids that are not scene objects only lower OA.
#include <cstdint>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "dataset/eval/label_overlap.h"

namespace pg::data::eval {

struct ObjectIou {
    int32_t id = 0;
    double iou = 0.0;
};

struct InstanceScores3d {
    std::vector<ObjectIou> objects;  // by id
    std::optional<double> miou;      // nullopt if the GT has no object
    std::optional<double> oa;
    uint64_t gaussians = 0;
};

// gt and pred label the same Gaussians; GT ids must be <= kMaxLabel (negative GT ids are
// treated as unlabelled: no object). Throws std::invalid_argument otherwise.
InstanceScores3d instance_scores_3d(std::span<const int32_t> gt, std::span<const int32_t> pred);

struct ViewScores {
    std::string name;
    std::vector<ObjectIou> objects;  // the objects of this view, by id
    std::optional<double> miou;      // nullopt if the view has none
};

struct ObjectIou2d {
    int32_t id = 0;
    double iou = 0.0;  // mean over the views where it is an object
    size_t views = 0;  // how many
};

struct InstanceScores2d {
    std::vector<ViewScores> views;      // in the order added
    std::vector<ObjectIou2d> objects;   // by id
    std::optional<double> miou;
    std::optional<double> oa;
    uint64_t pixels = 0;
};

// Accumulates views one at a time (each mask is dropped after add_view), so the result
// does not depend on the order views are added.
class InstanceMaskScorer {
public:
    explicit InstanceMaskScorer(std::vector<int32_t> scene_objects = {});
    // gt and pred are the same view's masks, same size.
    void add_view(std::string name, std::span<const uint16_t> gt, std::span<const uint16_t> pred);
    InstanceScores2d result() const;

private:
    struct IdCounts {
        int32_t id;
        uint64_t gt, pred, both;
    };
    struct View {
        std::string name;
        std::vector<IdCounts> ids;  // ids >= 1 seen in the view's GT or prediction
    };
    std::set<int32_t> objects_;
    std::vector<View> views_;
    LabelOverlap scratch_;
    uint64_t total_ = 0, agree_ = 0;
};

}  // namespace pg::data::eval

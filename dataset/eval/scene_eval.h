#pragma once
// Scores of one scene: the GT folder SUITE_DIR/<scene> against PRED_DIR/<scene>, which
// holds any of scene.ply (3D), masks/<camera>.png (2D and OA) and clicks.json.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "dataset/eval/click_metrics.h"
#include "dataset/eval/instance_metrics.h"
#include "dataset/eval/semantic_metrics.h"
#include "dataset/eval/suite_info.h"

namespace pg::data::eval {

struct SceneEval {
    std::string name;
    std::vector<InstanceInfo> instances;  // from meta.json, for names
    // Instance suites fill instance_*, semantic suites semantic_*; each only when the
    // prediction has the files it needs.
    std::optional<InstanceScores3d> instance_3d;
    std::optional<InstanceScores2d> instance_2d;
    std::optional<SemanticScores> semantic_3d, semantic_2d;
    std::vector<ObjectClicks> clicks;  // as read from clicks.json
    std::optional<ClickScores> click_scores;
};

// InputError naming the file for: a prediction folder with none of the three inputs, a
// prediction PLY with a different Gaussian count than the GT, a missing label property,
// a GT view without a predicted mask (or the reverse), masks of different sizes.
SceneEval evaluate_scene(const SuiteInfo& suite, const std::string& name, const std::filesystem::path& gt_scene,
                         const std::filesystem::path& pred_scene);

}  // namespace pg::data::eval

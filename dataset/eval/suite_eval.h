#pragma once
// `pointgauss eval`: every scene of a split that has a prediction folder, scored.
#include <filesystem>
#include <string>
#include <vector>

#include "dataset/eval/scene_eval.h"
#include "dataset/eval/suite_info.h"

namespace pg::data::eval {

struct SuiteEval {
    SuiteInfo info;
    std::string split;
    std::vector<SceneEval> scenes;    // split order
    std::vector<std::string> skipped; // split scenes with no folder in PRED_DIR
};

// InputError for: a missing PRED_DIR, a split scene listed in suite.json with no folder
// in SUITE_DIR, and a PRED_DIR holding no scene of the split. A non-empty `two_class` (a
// class name or id) scores the two-class view of that class (two_class.h).
SuiteEval evaluate_suite(const std::filesystem::path& gt_dir, const std::filesystem::path& pred_dir,
                         const std::string& split, const std::string& two_class = "");

}  // namespace pg::data::eval

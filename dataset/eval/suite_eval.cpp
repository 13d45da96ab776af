#include "dataset/eval/suite_eval.h"

#include <stdexcept>

#include "dataset/error.h"
#include "dataset/eval/two_class.h"

namespace pg::data::eval {

namespace fs = std::filesystem;

SuiteEval evaluate_suite(const fs::path& gt_dir, const fs::path& pred_dir, const std::string& split,
                         const std::string& two_class) {
    SuiteEval out;
    out.info = read_suite_json(gt_dir);
    if (!two_class.empty()) use_two_class_view(out.info, two_class);
    out.split = split;
    if (!fs::is_directory(pred_dir)) throw InputError(pred_dir.string(), "no such folder");
    const std::vector<std::string>* scenes = nullptr;
    try {
        scenes = &out.info.split(split);
    } catch (const std::invalid_argument& e) {
        throw InputError("--split", e.what());
    }
    if (scenes->empty()) throw InputError((gt_dir / "suite.json").string(), "split '" + split + "' lists no scene");

    for (const auto& name : *scenes) {
        const fs::path gt_scene = gt_dir / name, pred_scene = pred_dir / name;
        if (!fs::is_directory(gt_scene))
            throw InputError(gt_scene.string(), "scene listed in suite.json has no folder");
        if (!fs::is_directory(pred_scene)) {
            out.skipped.push_back(name);
            continue;
        }
        out.scenes.push_back(evaluate_scene(out.info, name, gt_scene, pred_scene));
    }
    if (out.scenes.empty())
        throw InputError(pred_dir.string(), "holds a folder for no scene of the " + split + " split (first: " +
                                                scenes->front() + ")");
    return out;
}

}  // namespace pg::data::eval

#include "dataset/eval/scene_eval.h"

#include <algorithm>

#include "dataset/error.h"
#include "dataset/json_file.h"
#include "dataset/eval/label_files.h"
#include "dataset/eval/two_class.h"

namespace pg::data::eval {

namespace fs = std::filesystem;

namespace {

std::string size_text(const Image16& m) { return std::to_string(m.width) + "x" + std::to_string(m.height); }

void check_gt_ids(const fs::path& file, const std::vector<int32_t>& ids) {
    for (int32_t v : ids)
        if (v < 0 || v > kMaxLabel)
            throw InputError(file.string(),
                             "label " + std::to_string(v) + " outside [0, " + std::to_string(kMaxLabel) + "]");
}

void score_gaussians(const SuiteInfo& suite, const fs::path& gt_ply, const fs::path& pred_ply,
                     const std::vector<int32_t>& class_ids, SceneEval& s) {
    const char* prop = suite.label_property();
    auto gt = read_gaussian_labels(gt_ply, prop);
    check_gt_ids(gt_ply, gt);
    auto pred = read_gaussian_labels(pred_ply, prop);
    if (pred.size() != gt.size())
        throw InputError(pred_ply.string(), std::to_string(pred.size()) + " Gaussians, the ground truth " +
                                                gt_ply.string() + " has " + std::to_string(gt.size()));
    if (suite.semantic()) {
        if (suite.two_class) {
            to_two_class(gt, suite.two_class->id);
            to_two_class(pred, suite.two_class->id);
        }
        s.semantic_3d = semantic_scores_3d(gt, pred, class_ids);
        return;
    }
    s.instance_3d = instance_scores_3d(gt, pred);
}

void score_masks(const SuiteInfo& suite, const fs::path& gt_dir, const fs::path& pred_dir,
                 const std::vector<int32_t>& class_ids, std::vector<int32_t> gt_objects, SceneEval& s) {
    const auto views = list_mask_views(gt_dir);
    if (views.empty()) throw InputError(gt_dir.string(), "holds no .png mask");
    for (const auto& v : list_mask_views(pred_dir))
        if (!std::binary_search(views.begin(), views.end(), v))
            throw InputError((pred_dir / (v + ".png")).string(), "no ground-truth mask for this view in " + gt_dir.string());

    InstanceMaskScorer instances(std::move(gt_objects));
    std::optional<LabelOverlap> classes;
    if (suite.semantic()) classes.emplace(size_t(kMaxLabel) + 1);
    for (const auto& v : views) {
        const fs::path gt_file = gt_dir / (v + ".png"), pred_file = pred_dir / (v + ".png");
        Image16 gt = read_mask(gt_file);
        if (!fs::exists(pred_file)) throw InputError(pred_file.string(), "missing: the ground truth has this view");
        Image16 pred = read_mask(pred_file);
        if (pred.width != gt.width || pred.height != gt.height)
            throw InputError(pred_file.string(), "mask is " + size_text(pred) + ", the ground truth " + gt_file.string() +
                                                     " is " + size_text(gt));
        if (suite.two_class) {
            to_two_class(gt.pixels, suite.two_class->id);
            to_two_class(pred.pixels, suite.two_class->id);
        }
        if (classes) classes->add(gt.pixels, pred.pixels);
        else instances.add_view(v, gt.pixels, pred.pixels);
    }
    if (classes) s.semantic_2d = semantic_scores(*classes, class_ids);
    else s.instance_2d = instances.result();
}

}  // namespace

// A semantic prediction's report.json names the model's classes; ids mean nothing when they are
// not the suite's.
void check_predicted_classes(const SuiteInfo& suite, const fs::path& pred_scene) {
    const fs::path report = pred_scene / "report.json";
    if (!suite.semantic() || !fs::exists(report)) return;
    const nlohmann::json j = read_json_file(report);
    if (!j.is_object() || j.value("mode", "") != "semantic" || !j.contains("classes") || !j["classes"].is_array()) return;
    std::string predicted, expected;
    for (const auto& c : j["classes"])
        if (c.is_object() && c.contains("name") && c["name"].is_string())
            predicted += (predicted.empty() ? "" : ", ") + c["name"].get<std::string>();
    for (const auto& c : suite.two_class ? suite.own_classes : suite.classes) expected += (expected.empty() ? "" : ", ") + c.name;
    if (predicted != expected)
        throw InputError(report.string(), "the model's classes (" + predicted + ") are not the suite's (" + expected +
                                              "): its class ids cannot be scored against this ground truth");
}

SceneEval evaluate_scene(const SuiteInfo& suite, const std::string& name, const fs::path& gt_scene,
                         const fs::path& pred_scene) {
    const fs::path pred_ply = pred_scene / "scene.ply", pred_masks = pred_scene / "masks",
                   clicks = pred_scene / "clicks.json";
    const bool has_ply = fs::exists(pred_ply), has_masks = fs::is_directory(pred_masks),
               has_clicks = fs::exists(clicks);
    if (!has_ply && !has_masks && !has_clicks)
        throw InputError(pred_scene.string(), "holds none of scene.ply, masks/, clicks.json");
    check_predicted_classes(suite, pred_scene);

    SceneEval s;
    s.name = name;
    s.instances = read_scene_instances(gt_scene);
    // 2D objects: meta.json's instances (plus GT mask ids), so a predicted object that a
    // view's GT misses still counts there, whichever files the prediction has.
    std::vector<int32_t> class_ids, gt_objects;
    for (const auto& c : suite.classes) class_ids.push_back(c.id);
    for (const auto& i : s.instances) gt_objects.push_back(i.id);

    if (has_ply) score_gaussians(suite, gt_scene / "scene.ply", pred_ply, class_ids, s);
    if (has_masks) score_masks(suite, gt_scene / "masks", pred_masks, class_ids, gt_objects, s);
    if (has_clicks) {
        s.clicks = read_clicks_json(clicks);
        s.click_scores = click_scores(s.clicks);
    }
    return s;
}

}  // namespace pg::data::eval

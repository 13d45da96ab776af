// pointgauss segment SCENE --cameras FILE --semantic: no clicks; every Gaussian gets a class
// (engine/segment/semantic_labeler.h), written as the scene's `class` property, one PLY per
// class, per-view class masks and overlays with a legend, and report.json.
#include <chrono>
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "app/cli/commands.h"
#include "app/cli/export_format.h"
#include "app/common/progress.h"
#include "app/common/ptv3_classifier.h"
#include "app/common/staged_output.h"
#include "app/common/up_arg.h"
#include "dataset/atomic_file.h"
#include "dataset/error.h"
#include "dataset/eval/suite_info.h"
#include "dataset/formats/camera_io.h"
#include "dataset/formats/scene_io.h"
#include "dataset/report/palette.h"
#include "engine/segment/export.h"
#include "engine/segment/label_raster.h"
#include "engine/vk/context.h"

namespace pg::app {

namespace fs = std::filesystem;

namespace {

// Class names of the suite a scene file lies in (SUITE/SCENE/scene.ply), if it is one.
std::vector<std::string> suite_class_names_near(const std::string& scene) {
    const fs::path suite = fs::absolute(scene).parent_path().parent_path();
    std::vector<std::string> names;
    if (!fs::exists(suite / "suite.json")) return names;
    for (const auto& c : data::eval::read_suite_json(suite).classes) {
        if (c.id != int32_t(names.size())) return {};
        names.push_back(c.name);
    }
    return names;
}

}  // namespace

void run_segment_semantic(const SemanticSegmentArgs& a) {
    scene_budget(a.device);
    const auto total_start = std::chrono::steady_clock::now();
    const std::string model = a.model.empty() ? default_semantic_model_path() : a.model;
    if (model.empty())
        throw data::InputError("--model", "the shipped model assets/models/semantic.safetensors was not found "
                                          "(set PG_SEMANTIC_MODEL or give --model FILE.safetensors)");
    const bool ground_truth = model == "ground-truth";
    if (!ground_truth && !fs::exists(model)) throw data::InputError("--model", "'" + model + "' does not exist");
    if (a.tile < 0) throw data::InputError("--tile", "must be positive (0: the model's)");
    const auto mode = seg::parse_label_mode(a.mode);
    auto cloud = load_scene_shown(a.scene, a.lod);
    auto cameras = data::load_cameras(a.cameras);
    std::vector<size_t> views;
    if (a.views != "none") views = select_views(a.views, cameras);

    const fs::path out(a.out);
    for (const std::string& f : {scene_file_for(a.export_format), std::string("report.json")})
        seg::refuse_overwriting(out / f, {a.scene, a.cameras, model});

    vk::ContextOptions co;
    co.device = a.device.device;
    vk::Context ctx(co);
    seg::SemanticLabelOptions o;
    o.up = resolve_up(a.up, cameras, cloud);
    o.tile = a.tile;
    o.seed = a.seed;
    seg::SemanticLabels labels;
    std::vector<std::string> names;
    int classes = 0;
    double tile = 0;
    if (ground_truth) {
        // An evaluation tool, as for clicks: the scene's own classes, so the 2D stages are measured alone.
        auto gt = cloud.int_property("class");
        if (!gt) throw data::InputError(a.scene, "has no integer property 'class' for the ground-truth model");
        names = suite_class_names_near(a.scene);
        for (int32_t c : *gt) classes = std::max(classes, c + 1);
        classes = std::max(classes, int(names.size()));
        labels.classes = std::move(*gt);
        labels.class_counts.assign(size_t(classes), 0);
        for (int32_t c : labels.classes) ++labels.class_counts[size_t(std::max(c, 0))];
    } else {
        Ptv3ClassNetwork network(ctx, model);
        names = network.config().class_names;
        classes = network.classes();
        tile = a.tile > 0 ? a.tile : network.tile_size();
        Progress progress("tiles", 100);
        o.progress = [&](size_t done, size_t total) { progress.set(total ? 100 * done / total : 100, "% of the tiles"); };
        labels = seg::label_by_class(cloud, network, o);
    }
    auto class_name = [&](int c) { return c < int(names.size()) ? names[size_t(c)] : "class_" + std::to_string(c); };
    std::map<std::string, double> stage_ms = labels.stage_ms;

    StagedOutput staged(out);  // every output appears at the end, or none
    const fs::path& stage = staged.dir();
    nlohmann::json report;
    report["scene"] = a.scene;
    report["device"] = ctx.info().name;
    report["model"] = model;
    report["mode"] = "semantic";
    report["gaussians"] = cloud.size();
    report["up"] = {o.up.x, o.up.y, o.up.z};
    report["tile"] = tile;
    report["tiles"] = labels.tiles;
    report["batches"] = labels.batches;
    report["forwards"] = labels.forwards;
    report["unvoted"] = labels.unvoted;
    std::vector<seg::ExportObject> present;
    for (int c = 0; c < classes; ++c) {
        report["classes"].push_back({{"id", c}, {"name", class_name(c)}, {"gaussians", labels.class_counts[size_t(c)]}});
        if (labels.class_counts[size_t(c)]) present.push_back({c, class_name(c)});
    }

    // 3D: the scene with its classes, one standard 3DGS file per class present.
    auto t0 = std::chrono::steady_clock::now();
    write_3d_outputs(ctx, a.export_format, cloud, labels.classes, "class", present, stage, "classes");
    stage_ms["write 3D"] = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

    // 2D: class masks (class ids; class 0 is also "nothing labelled") and tinted overlays with a legend.
    // No refinement: keeping one component per label would drop all but one building.
    if (!views.empty()) {
        render::GpuScene scene = upload_scene(ctx, cloud, a.device);
        seg::ViewExportOptions vo;
        vo.masks.mode = mode;
        vo.masks.refine = false;
        vo.colour = [](uint32_t c) { return data::report::class_colour(int(c)); };
        vo.legend.push_back({class_name(0) + " (no tint)", glm::vec3(1.0f)});
        for (int c = 1; c < classes; ++c) vo.legend.push_back({class_name(c), data::report::class_colour(c)});
        Progress views_progress("masks", views.size());
        vo.progress = [&](size_t, const std::string& view) {
            views_progress.step(view);
            return true;
        };
        for (auto& [name, ms] : seg::write_view_masks(ctx, scene, labels.classes, cameras, views, stage, vo))
            stage_ms[name] += ms;
        views_progress.finish();
        report["views"] = views.size();
    }
    for (auto& [name, ms] : stage_ms) report["stage_ms"][name] = ms;
    report["total_ms"] =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - total_start).count();
    data::write_atomically(stage / "report.json", [&](std::ostream& os) { os << report.dump(2) << "\n"; });
    staged.commit();

    std::printf("labelled %zu Gaussians by class (", cloud.size());
    for (size_t i = 0; i < present.size(); ++i)
        std::printf("%s%s: %zu", i ? ", " : "", present[i].name.c_str(), labels.class_counts[size_t(present[i].id)]);
    std::printf("), %zu tiles, %zu view(s) of masks, into %s\n", labels.tiles, views.size(), a.out.c_str());
}

}  // namespace pg::app

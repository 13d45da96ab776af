// pointgauss segment SCENE --cameras FILE --semantic: no clicks; every Gaussian gets a class
// (engine/segment/semantic_labeler.h), written as the scene's `class` property, one PLY per
// class, per-view class masks and overlays with a legend, and report.json.
#include <chrono>
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "app/cli/commands.h"
#include "app/common/progress.h"
#include "app/common/ptv3_classifier.h"
#include "app/common/up_arg.h"
#include "dataset/atomic_file.h"
#include "dataset/error.h"
#include "dataset/formats/camera_io.h"
#include "dataset/formats/scene_io.h"
#include "dataset/report/palette.h"
#include "engine/segment/export.h"
#include "engine/segment/label_raster.h"
#include "engine/vk/context.h"

namespace pg::app {

namespace fs = std::filesystem;

void run_segment_semantic(const SemanticSegmentArgs& a) {
    scene_budget(a.device);
    const auto total_start = std::chrono::steady_clock::now();
    const std::string model = a.model.empty() ? default_semantic_model_path() : a.model;
    if (model.empty())
        throw data::InputError("--model", "the shipped model assets/models/semantic.safetensors was not found "
                                          "(set PG_SEMANTIC_MODEL or give --model FILE.safetensors)");
    if (!fs::exists(model)) throw data::InputError("--model", "'" + model + "' does not exist");
    if (a.tile < 0) throw data::InputError("--tile", "must be positive (0: the model's)");
    const auto mode = seg::parse_label_mode(a.mode);
    auto cloud = load_scene_shown(a.scene);
    auto cameras = data::load_cameras(a.cameras);
    std::vector<size_t> views;
    if (a.views != "none") views = select_views(a.views, cameras);

    const fs::path out(a.out);
    if (fs::exists(out) && !fs::is_directory(out)) throw data::InputError(a.out, "exists and is not a folder");
    for (const char* f : {"scene.ply", "report.json"}) seg::refuse_overwriting(out / f, {a.scene, a.cameras, model});

    vk::ContextOptions co;
    co.device = a.device.device;
    vk::Context ctx(co);
    Ptv3ClassNetwork network(ctx, model);
    const auto& names = network.config().class_names;
    auto class_name = [&](int c) { return c < int(names.size()) ? names[size_t(c)] : "class_" + std::to_string(c); };

    seg::SemanticLabelOptions o;
    o.up = resolve_up(a.up, cameras, cloud);
    o.tile = a.tile;
    o.seed = a.seed;
    Progress progress("tiles", 100);
    o.progress = [&](size_t done, size_t total) { progress.set(total ? 100 * done / total : 100, "% of the tiles"); };
    const seg::SemanticLabels labels = seg::label_by_class(cloud, network, o);
    progress.finish();
    std::map<std::string, double> stage_ms = labels.stage_ms;

    fs::create_directories(out);
    nlohmann::json report;
    report["scene"] = a.scene;
    report["device"] = ctx.info().name;
    report["model"] = model;
    report["mode"] = "semantic";
    report["gaussians"] = cloud.size();
    report["up"] = {o.up.x, o.up.y, o.up.z};
    report["tile"] = a.tile > 0 ? a.tile : network.tile_size();
    report["tiles"] = labels.tiles;
    report["batches"] = labels.batches;
    report["forwards"] = labels.forwards;
    report["unvoted"] = labels.unvoted;
    std::vector<seg::ExportObject> present;
    for (int c = 0; c < network.classes(); ++c) {
        report["classes"].push_back({{"id", c}, {"name", class_name(c)}, {"gaussians", labels.class_counts[size_t(c)]}});
        if (labels.class_counts[size_t(c)]) present.push_back({c, class_name(c)});
    }

    // 3D: the scene with its classes, one standard 3DGS PLY per class present.
    auto t0 = std::chrono::steady_clock::now();
    seg::write_labelled_scene(cloud, labels.classes, out / "scene.ply", "class");
    seg::write_object_plys(cloud, labels.classes, present, out / "classes");
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
        for (int c = 1; c < network.classes(); ++c) vo.legend.push_back({class_name(c), data::report::class_colour(c)});
        Progress views_progress("masks", views.size());
        vo.progress = [&](size_t, const std::string& view) {
            views_progress.step(view);
            return true;
        };
        for (auto& [name, ms] : seg::write_view_masks(ctx, scene, labels.classes, cameras, views, out, vo))
            stage_ms[name] += ms;
        views_progress.finish();
        report["views"] = views.size();
    }
    for (auto& [name, ms] : stage_ms) report["stage_ms"][name] = ms;
    report["total_ms"] =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - total_start).count();
    data::write_atomically(out / "report.json", [&](std::ostream& os) { os << report.dump(2) << "\n"; });

    std::printf("labelled %zu Gaussians by class (", cloud.size());
    for (size_t i = 0; i < present.size(); ++i)
        std::printf("%s%s: %zu", i ? ", " : "", present[i].name.c_str(), labels.class_counts[size_t(present[i].id)]);
    std::printf("), %zu tiles, %zu view(s) of masks, into %s\n", labels.tiles, views.size(), a.out.c_str());
}

}  // namespace pg::app

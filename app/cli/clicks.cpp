// pointgauss clicks: the interactive benchmark protocol (InterObject3D / AGILE3D) on a suite.
// Every ground-truth object of every scene gets a simulated session: a 3D click at the most
// interior point of the largest error, the segmentation pipeline, the IoU, again, up to
// --max-clicks. Each scene's IoU curves go to PRED_DIR/<scene>/clicks.json for `eval`.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app/cli/commands.h"
#include "app/common/progress.h"
#include "app/common/staged_output.h"
#include "app/common/ptv3_decoder.h"
#include "app/common/up_arg.h"
#include "dataset/atomic_file.h"
#include "dataset/clicks/session.h"
#include "dataset/error.h"
#include "dataset/eval/click_metrics.h"
#include "dataset/eval/suite_info.h"
#include "dataset/formats/camera_io.h"
#include "dataset/formats/scene_io.h"
#include "dataset/up_axis.h"
#include "engine/segment/segmenter.h"
#include "engine/vk/context.h"
#include "nn/ptv3/weights.h"
#include "nn/safetensors.h"

namespace pg::app {

namespace fs = std::filesystem;
namespace clk = data::clicks;
using Clock = std::chrono::steady_clock;

namespace {

struct ClicksArgs {
    std::string gt, model, out, split = "test", scenes, up = "cameras", roi, decoder = "ptv3";
    std::string solver = "walk+forest", lift = "surface";
    int max_clicks = 20;
    size_t objects = 0;  // 0: every object
    double sigma = 0, scale = 0;
    std::vector<double> graph_scales{1.0, 2.0};
    uint64_t seed = 1;
    DeviceOptions device;
};

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

// The model file's config, read before the device starts so a wrong file fails early.
// Ptv3Decoder checks the same on construction; this only moves the error ahead.
void check_interactive_model(const std::string& path) {
    nn::Ptv3Config c;
    try {
        c = nn::Ptv3Weights::config_of(nn::SafeTensors::load(path));
    } catch (const nn::FormatError& e) {
        throw data::InputError("--model", e.what());
    }
    check_interactive_config(c, path);
}

// The scenes to run: the split, narrowed to --scenes (which must name scenes of that split).
std::vector<std::string> chosen_scenes(const ClicksArgs& a, const data::eval::SuiteInfo& suite) {
    const fs::path suite_file = fs::path(a.gt) / "suite.json";
    const auto& split = suite.split(a.split);
    if (a.scenes.empty()) {
        if (split.empty())
            throw data::InputError(suite_file.string(), "the " + a.split + " split lists no scene (try --split all)");
        return split;
    }
    std::vector<std::string> names;
    std::stringstream items(a.scenes);
    std::string name;
    while (std::getline(items, name, ',')) {
        if (std::find(suite.scenes.begin(), suite.scenes.end(), name) == suite.scenes.end())
            throw data::InputError("--scenes", "no scene '" + name + "' in " + suite_file.string());
        if (std::find(split.begin(), split.end(), name) == split.end())
            throw data::InputError("--scenes", "scene '" + name + "' is not in the " + a.split +
                                                   " split (try --split all)");
        if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
    }
    if (names.empty()) throw data::InputError("--scenes", "names no scene");
    return names;
}

fs::path camera_file(const fs::path& scene_dir) {
    if (fs::exists(scene_dir / "cameras.json")) return scene_dir / "cameras.json";
    if (fs::is_directory(scene_dir / "sparse" / "0")) return scene_dir / "sparse" / "0";
    throw data::InputError(scene_dir.string(), "holds neither cameras.json nor sparse/0");
}

// The objects of a scene: its non-zero label values, ascending; names from meta.json
// (instances) or the suite's classes (semantic suites).
std::vector<std::pair<int32_t, std::string>> scene_objects(const std::vector<int32_t>& labels,
                                                           const data::eval::SuiteInfo& suite,
                                                           const fs::path& scene_dir) {
    std::map<int32_t, std::string> names;
    if (suite.semantic())
        for (const auto& c : suite.classes) names[c.id] = c.name;
    else
        for (const auto& i : data::eval::read_scene_instances(scene_dir)) names[i.id] = i.name;
    std::set<int32_t> ids;
    for (int32_t v : labels)
        if (v > 0) ids.insert(v);
    std::vector<std::pair<int32_t, std::string>> out;
    for (int32_t id : ids) {
        auto it = names.find(id);
        out.push_back({id, it != names.end() && !it->second.empty() ? it->second : "object_" + std::to_string(id)});
    }
    return out;
}

void run_clicks(const ClicksArgs& a) {
    // Every check on the input comes before the device starts and before anything is written.
    if (a.max_clicks < 1) throw data::InputError("--max-clicks", "must be at least 1");
    const auto graph_use = seg::parse_graph_use(a.decoder, "--decoder");
    const auto solver = seg::parse_graph_solver(a.solver, "--graph-solver");
    const auto lift = seg::parse_lift_rule(a.lift, "--lift");
    const bool network = graph_use != seg::GraphUse::Alone;
    if (network && a.model.empty()) throw data::InputError("--model", "is needed by the " + a.decoder + " decoder");
    const bool ground_truth = a.model == "ground-truth";
    if (network && !ground_truth && !fs::is_regular_file(a.model))
        throw data::InputError("--model", "'" + a.model + "' is neither ground-truth nor an existing model file");
    if (network && !ground_truth) check_interactive_model(a.model);
    const auto suite = data::eval::read_suite_json(a.gt);
    const auto scenes = chosen_scenes(a, suite);
    for (const auto& name : scenes) {
        const fs::path dir = fs::path(a.gt) / name;
        if (!fs::is_regular_file(dir / "scene.ply")) throw data::InputError((dir / "scene.ply").string(), "no such file");
        camera_file(dir);
    }
    const fs::path out(a.out);
    if (fs::exists(out) && fs::equivalent(out, a.gt))
        throw data::InputError("--out", "is the suite folder; predictions go to a folder of their own");
    seg::SegmentOptions o;
    o.graph = graph_use;
    o.graph_scales = checked_graph_scales(a.graph_scales);
    o.solver = solver;
    o.lift = lift;
    o.sigma = a.sigma;
    o.scale = a.scale;
    o.seed = a.seed;
    if (!a.roi.empty()) parse_roi(a.roi, o.roi_length, o.roi_width);
    if (a.up != "cameras" && a.up != "ground") parse_up(a.up);
    // Every scene's clicks.json appears at the end, or none (beside what OUT already holds).
    StagedOutput staged(out);

    vk::ContextOptions co;
    co.device = a.device.device;
    vk::Context ctx(co);
    // One PTv3 on the device serves every scene.
    std::unique_ptr<Ptv3Decoder> ptv3;
    if (network && !ground_truth) ptv3 = std::make_unique<Ptv3Decoder>(ctx, a.model);

    const auto run_start = Clock::now();
    std::vector<data::eval::ObjectClicks> all;
    size_t clicks_total = 0;
    for (const auto& name : scenes) {
        const fs::path dir = fs::path(a.gt) / name;
        const auto scene_start = Clock::now();
        const size_t clicks_before = clicks_total;
        const auto cloud = data::load_scene(dir / "scene.ply");
        const auto cameras = data::load_cameras(camera_file(dir));
        const auto labels = cloud.int_property(suite.label_property());
        if (!labels)
            throw data::InputError((dir / "scene.ply").string(),
                                   std::string("has no integer vertex property '") + suite.label_property() + "'");
        auto objects = scene_objects(*labels, suite, dir);
        if (a.objects > 0 && objects.size() > a.objects) objects.resize(a.objects);
        o.up = resolve_up(a.up, cameras, cloud);

        render::GpuScene gpu_scene(ctx, cloud);
        if (ptv3) ptv3->set_scene(&cloud);
        std::unique_ptr<seg::Decoder> gt_decoder;
        if (network && ground_truth) gt_decoder = std::make_unique<seg::GroundTruthDecoder>(*labels);
        seg::Decoder* decoder = !network ? nullptr : ground_truth ? gt_decoder.get() : static_cast<seg::Decoder*>(ptv3.get());
        auto segmenter = decoder ? std::make_unique<seg::Segmenter>(ctx, cloud, gpu_scene, cameras, *decoder)
                                 : std::make_unique<seg::Segmenter>(ctx, cloud, gpu_scene, cameras);
        const std::string decoder_name =
            graph_use == seg::GraphUse::None ? decoder->name()
            : decoder ? std::string(seg::graph_use_name(graph_use)) + " (" + decoder->name() + ")"
                      : std::string("graph");
        const clk::Clicker3D clicker(cloud.mean);
        clk::SessionOptions so;
        so.max_clicks = a.max_clicks;

        nlohmann::json report{{"scene", name},          {"decoder", decoder_name}, {"device", ctx.info().name},
                              {"gaussians", cloud.size()}, {"max_clicks", a.max_clicks},
                              {"up", {o.up.x, o.up.y, o.up.z}}, {"objects", nlohmann::json::array()}};
        Progress progress(name, objects.size());
        for (const auto& [id, obj_name] : objects) {
            const auto t0 = Clock::now();
            clk::Mask gt = clk::mask_of(*labels, id);
            const size_t gt_size = clk::count(gt);
            auto session = clk::make_session_3d(clicker, std::move(gt), so);
            const auto result = session.run([&, id = id, obj_name = obj_name](const std::vector<clk::Click3D>& clicks) {
                data::Prompts prompts;
                data::ObjectPrompt op;
                op.id = id;
                op.name = obj_name;
                for (const auto& c : clicks) {
                    data::PromptClick pc;
                    pc.point = glm::dvec3(c.position);
                    pc.positive = c.positive;
                    op.clicks.push_back(pc);
                }
                prompts.objects.push_back(std::move(op));
                try {
                    return clk::mask_of(segmenter->segment(prompts, o).labels, id);
                } catch (const data::InputError& e) {
                    throw data::InputError(flag_for(e.where()), e.reason());
                }
            });
            const double ms = ms_since(t0);
            nlohmann::json jo{{"id", id}, {"name", obj_name}, {"gaussians", gt_size}, {"ms", ms},
                              {"clicks", nlohmann::json::array()}, {"iou_per_click", result.iou_per_click}};
            for (const auto& c : result.clicks)
                jo["clicks"].push_back({{"gaussian", c.index},
                                        {"position", {c.position.x, c.position.y, c.position.z}},
                                        {"positive", c.positive}});
            report["objects"].push_back(std::move(jo));
            all.push_back({id, result.iou_per_click});
            clicks_total += result.clicks.size();
            progress.step(obj_name);
        }
        progress.finish();
        report["total_ms"] = ms_since(scene_start);
        fs::create_directories(staged.dir() / name);
        data::write_atomically(staged.dir() / name / "clicks.json", [&](std::ostream& os) { os << report.dump(2) << "\n"; });
        if (!isatty(2) || std::getenv("CI")) {  // a log line per scene where no progress line shows
            std::printf("%s: %zu object(s), %zu click(s), %.1f s\n", name.c_str(), objects.size(),
                        clicks_total - clicks_before, ms_since(scene_start) / 1000.0);
            std::fflush(stdout);  // as it happens, also into a log file
        }
    }
    staged.commit();

    const double seconds = ms_since(run_start) / 1000.0;
    std::printf("clicks: %zu object(s) in %zu scene(s), %zu click(s), %.1f s, into %s\n", all.size(), scenes.size(),
                clicks_total, seconds, a.out.c_str());
    if (auto s = data::eval::click_scores(all)) {
        // kIouAtClicks = {1, 3, 5, 10}, kNocThresholds = {0.80, 0.85, 0.90}.
        std::printf("IoU@1 %.2f  IoU@5 %.2f  NoC@85 %.2f\n", 100.0 * s->iou_at[0], 100.0 * s->iou_at[2], s->noc[1]);
    }
}

}  // namespace

void register_clicks(CLI::App& app, std::function<void()>& run) {
    auto a = std::make_shared<ClicksArgs>();
    auto* cmd = app.add_subcommand("clicks", "Simulate interactive sessions on a benchmark suite: clicks.json per scene for eval");
    cmd->add_option("--gt", a->gt, "Suite folder written by `pointgauss synth` (holds suite.json)")->required();
    cmd->add_option("--model", a->model, "The network: a PTv3 model file (.safetensors), or ground-truth (the scene's labels); not needed by --decoder graph");
    cmd->add_option("--decoder", a->decoder, "ptv3 (the network alone, the paper's protocol), graph or ptv3+graph (see segment)")
        ->capture_default_str();
    cmd->add_option("--lift", a->lift, "Where a click in a view lands: surface or tau (see segment)")->capture_default_str();
    cmd->add_option("--graph-solver", a->solver, "Graph decoders: walk, forest or walk+forest (see segment)")->capture_default_str();
    cmd->add_option("--graph-scales", a->graph_scales, "Graph decoders: the ROI scales solved (see segment)")->delimiter(',')->capture_default_str();
    cmd->add_option("--out", a->out, "Prediction folder: <scene>/clicks.json is written")->required();
    cmd->add_option("--split", a->split, "Scenes to run: test (default), train or all")
        ->check(CLI::IsMember({"test", "train", "all"}));
    cmd->add_option("--scenes", a->scenes, "Only these scenes of the split (comma list)");
    cmd->add_option("--objects", a->objects, "At most this many objects per scene (0: all)")->capture_default_str();
    cmd->add_option("--max-clicks", a->max_clicks, "Clicks per object at most")->capture_default_str();
    cmd->add_option("--up", a->up, "Up axis: cameras, ground, or x,y,z / -y ...")->capture_default_str();
    cmd->add_option("--scale", a->scale, "Typical object size (default: from the cameras)");
    cmd->add_option("--sigma", a->sigma, "Click weight fall-off in scene units (default: 0.4 x scale)");
    cmd->add_option("--roi", a->roi, "ROI length,width in scene units (default: 2.5 x scale each)");
    cmd->add_option("--seed", a->seed, "Partition seed")->capture_default_str();
    add_device_option(*cmd, a->device);
    cmd->callback([a, &run] { run = [a] { run_clicks(*a); }; });
}

}  // namespace pg::app

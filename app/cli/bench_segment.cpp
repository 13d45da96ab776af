// pointgauss bench segment: per-stage milliseconds for one click (lift, encode + ROI,
// partition, decode) and for the masks of one view (render, label raster, refine), medians
// over repeated runs.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <memory>

#include <nlohmann/json.hpp>

#include "app/cli/commands.h"
#include "app/common/host_memory.h"
#include "app/common/progress.h"
#include "dataset/error.h"
#include "dataset/formats/camera_io.h"
#include "dataset/formats/scene_io.h"
#include "dataset/prompts.h"
#include "dataset/up_axis.h"
#include "engine/segment/mask_views.h"
#include "engine/segment/segmenter.h"
#include "engine/segment/warm_up.h"
#include "engine/vk/buffer.h"
#include "engine/vk/context.h"

namespace pg::app {

namespace {

struct BenchSegmentArgs {
    std::string scene, cameras, prompts, mode = "occlusion", label_property = "instance", decoder = "ptv3";
    int lod = 0;
    int repeats = 5;
    bool json = false, coarse_answer = false, warm_up = false;
    std::vector<double> graph_scales{1.0, 2.0};
    uint64_t graph_budget = seg::SegmentOptions{}.graph_budget;
    uint64_t graph_focus = seg::SegmentOptions{}.graph_focus;
    DeviceOptions device;
};

void run_bench_segment(const BenchSegmentArgs& a) {
    scene_budget(a.device);  // a bad --max-device-memory fails before anything loads
    if (a.repeats < 1) throw data::InputError("--repeats", "must be at least 1");
    auto cloud = load_scene_shown(a.scene, a.lod);
    auto cameras = data::load_cameras(a.cameras);
    auto prompts = data::read_prompts(a.prompts);
    // One click of the first object: the interactive unit of work; with a graph decoder the
    // first click of every object (they are solved together).
    const auto graph = seg::parse_graph_use(a.decoder, "--decoder");
    data::Prompts one;
    for (auto& obj : prompts.objects)
        if (one.objects.empty() || graph != seg::GraphUse::None) {
            one.objects.push_back(obj);
            one.objects.back().clicks.resize(1);
        }
    // The graph decoder alone needs no labels (any capture); the network's stand-in does.
    auto labels = cloud.int_property(a.label_property);
    if (!labels && graph != seg::GraphUse::Alone)
        throw data::InputError(a.scene, "has no integer property '" + a.label_property + "'");

    vk::ContextOptions co;
    co.device = a.device.device;
    co.quiet = a.json;
    vk::Context ctx(co);
    render::GpuScene scene = upload_scene(ctx, cloud, a.device);
    std::unique_ptr<seg::GroundTruthDecoder> decoder;
    if (labels) decoder = std::make_unique<seg::GroundTruthDecoder>(*labels);
    auto make_segmenter = [&] {
        return decoder ? std::make_unique<seg::Segmenter>(ctx, cloud, scene, cameras, *decoder)
                       : std::make_unique<seg::Segmenter>(ctx, cloud, scene, cameras);
    };
    std::unique_ptr<seg::Segmenter> owned = make_segmenter();
    seg::Segmenter& segmenter = *owned;
    seg::SegmentOptions o;
    o.up = data::up_from_cameras(cameras);
    o.graph = graph;
    o.graph_scales = checked_graph_scales(a.graph_scales);
    o.graph_budget = a.graph_budget;
    o.graph_focus = a.graph_focus;
    // The viewer's path: a cold solve first hands over the coarse graph's answer.
    auto t0 = std::chrono::steady_clock::now();
    double coarse_ms = -1, run_coarse_ms = -1;
    double* coarse_into = &coarse_ms;  // the run being timed's
    if (a.coarse_answer)
        o.on_coarse = [&](const seg::SegmentResult&) {
            if (*coarse_into < 0) *coarse_into = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        };

    // The masks are timed in the first click's view (the first camera for a click given in 3D).
    const auto& click = one.objects.front().clicks.front();
    auto cam = click.point ? cameras.begin()
                           : std::find_if(cameras.begin(), cameras.end(), [&](auto& c) { return c.name == click.view; });
    if (cam == cameras.end()) throw data::InputError(a.prompts, "the first click's view is not among the cameras");

    // The viewer's path: the pipelines built while the scene loads, before the first click.
    double warm_up_ms = -1;
    if (a.warm_up) {
        const auto w0 = std::chrono::steady_clock::now();
        seg::warm_up(ctx, o, one.objects.size());
        segmenter.index_columns(o.up);  // as the viewer's warm-up
        warm_up_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - w0).count();
    }

    std::map<std::string, std::vector<double>> click_ms, view_ms;
    std::vector<double> click_total, view_total;
    double cold_ms = 0;
    std::map<std::string, double> cold_stage_ms;
    seg::SegmentResult result;
    for (int r = 0; r < a.repeats + 1; ++r) {  // the first run warms pipelines and buffers up
        t0 = std::chrono::steady_clock::now();
        try {
            result = segmenter.segment(one, o);
        } catch (const data::InputError& e) {
            throw data::InputError(flag_for(e.where()), e.reason());
        }
        double total = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        if (r == 0) {
            cold_ms = total;
            cold_stage_ms = result.stage_ms;
            continue;
        }
        for (auto& [k, v] : result.stage_ms) click_ms[k].push_back(v);
        click_total.push_back(total);
    }
    // A click on new objects once the pipelines exist (the graph built, a solve from scratch), the
    // median of `repeats`: on the same Segmenter with its domain forgotten, what a running viewer
    // pays (the scene's column index and the clicked view's pixel bins kept), and on a new
    // Segmenter, what a new process pays beside its pipelines.
    struct Fresh {
        std::map<std::string, double> stage_ms;
        double ms = 0, coarse_ms = -1;
    };
    auto fresh_clicks = [&](bool new_segmenter) {
        std::map<std::string, std::vector<double>> stage_runs;
        std::vector<double> runs, coarse_runs;
        for (int r = 0; r < a.repeats; ++r) {
            std::unique_ptr<seg::Segmenter> made;
            if (new_segmenter) made = make_segmenter();
            else segmenter.forget_domain();
            run_coarse_ms = -1;
            coarse_into = &run_coarse_ms;
            t0 = std::chrono::steady_clock::now();
            for (auto& [k, v] : (made ? *made : segmenter).segment(one, o).stage_ms) stage_runs[k].push_back(v);
            runs.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
            if (run_coarse_ms >= 0) coarse_runs.push_back(run_coarse_ms);
        }
        Fresh f;
        for (auto& [k, v] : stage_runs) f.stage_ms[k] = median(v);
        f.ms = median(runs);
        if (!coarse_runs.empty()) f.coarse_ms = median(coarse_runs);
        return f;
    };
    const Fresh new_domain = fresh_clicks(false), new_process = fresh_clicks(true);
    seg::MaskViews masker(ctx, scene, result.labels);
    seg::MaskViewsOptions mo;
    mo.mode = seg::parse_label_mode(a.mode);
    std::map<std::string, double> before;
    for (int r = 0; r < a.repeats + 1; ++r) {
        before = masker.stage_ms();
        auto t0 = std::chrono::steady_clock::now();
        masker.render(*cam, mo, false);
        double total = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        if (r == 0) continue;
        for (auto& [k, v] : masker.stage_ms()) view_ms[k].push_back(v - before[k]);
        view_total.push_back(total);
    }

    nlohmann::json j;
    j["device"] = ctx.info().name;
    j["gaussians"] = cloud.size();
    j["roi_gaussians"] = result.objects.front().roi_gaussians;
    // The graph decoders' cost follows the domain: the ROI columns at the largest scale and the margin.
    const size_t domain = result.graph ? result.graph->domain : 0;
    if (result.graph) j["graph_domain_nodes"] = domain;
    j["view"] = {cam->name, cam->width, cam->height};
    for (auto& [k, v] : click_ms) j["click_ms"][k] = median(v);
    j["click_ms"]["wall"] = median(click_total);
    j["decoder"] = a.decoder;
    j["objects"] = one.objects.size();
    j["first_click_wall_ms"] = cold_ms;  // the first run: pipelines (unless warmed up), buffers, the graph built, a cold solve
    if (warm_up_ms >= 0) j["warm_up_ms"] = warm_up_ms;
    for (auto& [k, v] : cold_stage_ms) j["first_click_ms"][k] = v;
    if (coarse_ms >= 0) j["first_click_coarse_answer_ms"] = coarse_ms;
    for (const auto& [key, f] : {std::pair<std::string, const Fresh&>{"new_domain", new_domain}, {"new_segmenter", new_process}}) {
        j[key + "_click_wall_ms"] = f.ms;
        for (auto& [k, v] : f.stage_ms) j[key + "_click_ms"][k] = v;
        if (f.coarse_ms >= 0) j[key + "_coarse_answer_ms"] = f.coarse_ms;
    }
    for (auto& [k, v] : view_ms) j["view_gpu_ms"][k] = median(v);
    j["view_wall_ms"] = median(view_total);
    const auto mem = vk::memory_stats();
    j["peak_device_bytes"] = mem.peak;
    j["peak_host_bytes"] = peak_host_bytes();
    if (a.json) {
        std::printf("%s\n", j.dump(2).c_str());
        return;
    }
    const std::string graph_nodes = result.graph ? ", graph domain " + std::to_string(domain) : "";
    std::printf("device %s, %zu Gaussians, ROI %zu%s, view %s %dx%d, median of %d\n\n", ctx.info().name.c_str(),
                cloud.size(), result.objects.front().roi_gaussians, graph_nodes.c_str(), cam->name.c_str(), cam->width,
                cam->height, a.repeats);
    // The first run (cold: pipelines, buffers, the graph built, a solve from scratch) beside the
    // repeats' medians (warm: what a further click on the same objects costs) and clicks on new
    // objects once the pipelines exist (medians: the graph built, a solve from scratch), on the
    // same Segmenter (new domain) and on a new one (new segmenter).
    std::printf("| one click (wall ms) | repeated (median) | first | new domain | new segmenter |\n"
                "|---|---:|---:|---:|---:|\n");
    for (auto& [k, v] : cold_stage_ms) click_ms[k];  // stages only a cold run has (a coarse start)
    for (const Fresh* f : {&new_domain, &new_process})
        for (auto& [k, v] : f->stage_ms) click_ms[k];
    auto num = [](double x) {
        char b[32];
        std::snprintf(b, sizeof b, "%.2f", x);
        return std::string(b);
    };
    auto cell = [&](const std::map<std::string, double>& m, const std::string& k) {
        auto it = m.find(k);
        return it == m.end() ? std::string("-") : num(it->second);
    };
    for (auto& [k, v] : click_ms)
        std::printf("| %s | %s | %s | %s | %s |\n", k.c_str(), v.empty() ? "-" : num(median(v)).c_str(),
                    cell(cold_stage_ms, k).c_str(), cell(new_domain.stage_ms, k).c_str(),
                    cell(new_process.stage_ms, k).c_str());
    if (coarse_ms >= 0 || new_domain.coarse_ms >= 0 || new_process.coarse_ms >= 0)
        std::printf("| coarse answer shown (viewer) | - | %.2f | %.2f | %.2f |\n", coarse_ms, new_domain.coarse_ms,
                    new_process.coarse_ms);
    if (warm_up_ms >= 0) std::printf("| warm-up before the first click (--warm-up) | - | %.2f | - | - |\n", warm_up_ms);
    std::printf("| **total** | %.2f | %.2f | %.2f | %.2f |\n\n", median(click_total), cold_ms, new_domain.ms,
                new_process.ms);
    std::printf("| masks of one view (GPU ms) | median |\n|---|---:|\n");
    for (auto& [k, v] : view_ms) std::printf("| %s | %.2f |\n", k.c_str(), median(v));
    std::printf("| **wall** | %.2f |\n", median(view_total));
    std::printf("\npeak device memory %.1f MiB, peak host memory %.1f MiB\n", double(mem.peak) / (1 << 20),
                double(peak_host_bytes()) / (1 << 20));
}

}  // namespace

void register_bench_segment(CLI::App& bench, std::function<void()>& run) {
    auto a = std::make_shared<BenchSegmentArgs>();
    auto* cmd = bench.add_subcommand("segment", "Per-stage ms for one click and for the masks of one view");
    add_scene_option(*cmd, a->scene, a->lod,
                     "A scene; labelled (the ground-truth decoder stands in for the network) unless --decoder graph");
    cmd->add_option("--cameras", a->cameras, "Camera file or COLMAP folder")->required();
    cmd->add_option("--prompts", a->prompts, "prompts.json; its first click is measured")->required();
    cmd->add_option("--mode", a->mode, "Label projection: occlusion or paper")->capture_default_str();
    cmd->add_option("--repeats", a->repeats, "Measured repetitions")->capture_default_str();
    cmd->add_option("--decoder", a->decoder, "ptv3 (the ground truth stands in for the network), graph or ptv3+graph (all objects' first clicks, solved together; repeats start warm)")->capture_default_str();
    cmd->add_option("--graph-scales", a->graph_scales, "Graph decoders: the ROI scales solved (as segment --graph-scales)")->delimiter(',')->capture_default_str();
    cmd->add_option("--graph-budget", a->graph_budget, "Graph decoders: a click's budget in nodes (as segment --graph-budget; 0: none)")->capture_default_str();
    cmd->add_option("--graph-focus", a->graph_focus, "Graph decoders: past this many nodes the fine graph covers the objects' coarse answers (as segment --graph-focus; 0: never)")->capture_default_str();
    cmd->add_option("--label-property", a->label_property, "Property the ground-truth decoder reads")
        ->capture_default_str();
    cmd->add_flag("--json", a->json, "Print JSON instead of tables");
    cmd->add_flag("--coarse-answer", a->coarse_answer,
                  "Graph decoders: time the viewer's path, where a cold solve first hands over the coarse graph's answer");
    cmd->add_flag("--warm-up", a->warm_up,
                  "Build the segmentation pipelines on a made-up scene and the scene's column index before the first click, "
                  "as the viewer does while its scene loads (its time is reported apart, not in the first click)");
    add_device_option(*cmd, a->device);
    add_memory_option(*cmd, a->device);
    cmd->callback([a, &run] { run = [a] { run_bench_segment(*a); }; });
}

}  // namespace pg::app

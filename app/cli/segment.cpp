// pointgauss segment: clicks in, 3D labels and per-view masks out.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include <nlohmann/json.hpp>

#include "app/cli/commands.h"
#include "app/cli/export_format.h"
#include "app/common/progress.h"
#include "app/common/ptv3_decoder.h"
#include "app/common/staged_output.h"
#include "app/common/up_arg.h"
#include "dataset/atomic_file.h"
#include "dataset/error.h"
#include "dataset/formats/camera_io.h"
#include "dataset/formats/scene_io.h"
#include "dataset/prompts.h"
#include "dataset/up_axis.h"
#include "engine/segment/export.h"
#include "engine/segment/label_raster.h"
#include "engine/segment/segmenter.h"
#include "engine/vk/context.h"

namespace pg::app {

namespace fs = std::filesystem;

namespace {

struct SegmentArgs {
    std::string scene, cameras, prompts, out, model, views = "all", mode = "occlusion", up = "cameras";
    int lod = 0;
    std::string export_format = "ply";
    std::string roi, label_property = "instance", decoder;  // empty: graph, or ptv3+graph when --model is given
    std::string solver = "walk+forest", lift = "surface", preconditioner = "multigrid";
    double sigma = 0, scale = 0;
    bool no_refine = false, strict = false, semantic = false;
    double tile = 0;
    seg::GraphOptions graph;
    seg::WalkOptions walk;
    float unary = 1.0f, unary_confidence = 0.97f, walk_sure = 0.7f;
    seg::ObjectSplitOptions splits;
    double unary_clean = seg::SegmentOptions{}.unary_clean;
    uint32_t coarse = 8;
    uint64_t graph_max_nodes = 0, graph_budget = seg::SegmentOptions{}.graph_budget;
    uint64_t graph_focus = seg::SegmentOptions{}.graph_focus;
    double margin = seg::SegmentOptions{}.graph_margin;
    std::vector<double> scales{1.0, 2.0};
    double scale_ratio = 0.25;
    uint64_t seed = 1;
    DeviceOptions device;
};

void run_segment(const SegmentArgs& args);

}  // namespace

const std::vector<double>& checked_graph_scales(const std::vector<double>& scales) {
    for (double f : scales)
        if (!(f > 0 && std::isfinite(f))) throw data::InputError("--graph-scales", "expected factors > 0, got " + std::to_string(f));
    return scales;
}

void parse_roi(const std::string& spec, double& length, double& width) {
    char extra;
    if (std::sscanf(spec.c_str(), "%lf,%lf%c", &length, &width, &extra) != 2 || !(length > 0 && width > 0))
        throw data::InputError("--roi", "expected length,width > 0, got '" + spec + "'");
}

std::string flag_for(const std::string& where) {
    for (const char* p : {"sigma", "roi", "decoder", "graph-k", "graph-shells"})
        if (where == p) return "--" + where;
    return where;
}

std::string with_flags(const std::string& error) {
    const size_t colon = error.find(": ");
    if (colon == std::string::npos) return error;
    return flag_for(error.substr(0, colon)) + error.substr(colon);
}

namespace {

void run_segment(const SegmentArgs& args) {
    scene_budget(args.device);  // a bad --max-device-memory fails before anything loads
    auto total_start = std::chrono::steady_clock::now();
    SegmentArgs a = args;
    // A model named without a decoder is meant to be used: the network with the graph.
    if (a.decoder.empty()) a.decoder = a.model.empty() ? "graph" : "ptv3+graph";
    const auto graph_use = seg::parse_graph_use(a.decoder, "--decoder");
    const auto solver = seg::parse_graph_solver(a.solver, "--graph-solver");
    const auto lift = seg::parse_lift_rule(a.lift, "--lift");
    const bool network = graph_use != seg::GraphUse::Alone;
    if (a.model.empty() && network) a.model = default_model_path();
    if (a.model.empty() && network)
        throw data::InputError("--model", "the shipped model assets/models/interactive.safetensors was not found "
                                          "(set PG_MODEL or give --model FILE.safetensors, or ground-truth on a "
                                          "labelled scene)");
    const bool ground_truth = a.model == "ground-truth";
    if (network && !ground_truth && !fs::exists(a.model))
        throw data::InputError("--model", "'" + a.model + "' is neither ground-truth nor an existing model file");
    auto mode = seg::parse_label_mode(a.mode);
    auto cloud = load_scene_shown(a.scene, a.lod);
    auto cameras = data::load_cameras(a.cameras);
    auto prompts = data::read_prompts(a.prompts);
    std::vector<size_t> views;
    if (a.views != "none") views = select_views(a.views, cameras);
    seg::SegmentOptions o;
    o.up = resolve_up(a.up, cameras, cloud);
    o.sigma = a.sigma;
    o.scale = a.scale;
    o.seed = a.seed;
    o.strict = a.strict;
    o.graph = graph_use;
    o.graph_options = a.graph;
    o.walk = a.walk;
    if (a.preconditioner == "jacobi") o.walk.preconditioner = seg::WalkPreconditioner::Jacobi;
    else if (a.preconditioner == "multigrid") o.walk.preconditioner = seg::WalkPreconditioner::Multigrid;
    else throw data::InputError("--walk-preconditioner", "expected jacobi or multigrid, got '" + a.preconditioner + "'");
    o.unary = a.unary;
    o.unary_confidence = a.unary_confidence;
    o.unary_clean = a.unary_clean;
    o.coarse_stride = a.coarse;
    o.graph_max_nodes = a.graph_max_nodes;
    o.graph_budget = a.graph_budget;
    o.graph_focus = a.graph_focus;
    o.graph_margin = a.margin;
    if (!(a.scale_ratio > 0 && a.scale_ratio <= 1))
        throw data::InputError("--graph-scale-ratio", "expected a ratio in (0, 1], got " + std::to_string(a.scale_ratio));
    o.graph_scales = checked_graph_scales(a.scales);
    o.graph_scale_ratio = a.scale_ratio;
    o.solver = solver;
    o.walk_sure = a.walk_sure;
    o.object_splits = a.splits;
    o.lift = lift;
    if (!a.roi.empty()) parse_roi(a.roi, o.roi_length, o.roi_width);
    auto gt = cloud.int_property(a.label_property);
    if (network && ground_truth && !gt)
        throw data::InputError(a.scene, "has no integer property '" + a.label_property +
                                            "' for the ground-truth decoder");

    fs::path out(a.out);
    for (const std::string& f : {scene_file_for(a.export_format), std::string("report.json")})
        seg::refuse_overwriting(out / f, {a.scene, a.cameras, a.prompts});
    StagedOutput staged(out);  // every output appears at the end, or none
    const fs::path& stage = staged.dir();

    vk::ContextOptions co;
    co.device = a.device.device;
    vk::Context ctx(co);
    render::GpuScene scene = upload_scene(ctx, cloud, a.device);
    std::unique_ptr<seg::Decoder> decoder;
    if (network && ground_truth) decoder = std::make_unique<seg::GroundTruthDecoder>(*gt);
    else if (network) decoder = std::make_unique<Ptv3Decoder>(ctx, a.model, &cloud);
    auto segmenter = decoder ? std::make_unique<seg::Segmenter>(ctx, cloud, scene, cameras, *decoder)
                             : std::make_unique<seg::Segmenter>(ctx, cloud, scene, cameras);
    seg::SegmentResult result;
    try {
        result = segmenter->segment(prompts, o);
    } catch (const data::InputError& e) {
        throw data::InputError(flag_for(e.where()), e.reason());
    }
    for (auto& obj : result.objects) obj.error = with_flags(obj.error);
    const size_t failed = result.failed();
    if (failed == result.objects.size())
        throw data::InputError(a.prompts, "no object could be segmented; the first: " + result.objects[0].error);
    for (auto& obj : result.objects)
        if (!obj.error.empty()) std::fprintf(stderr, "error: %s (the object is left out)\n", obj.error.c_str());

    nlohmann::json report;
    report["scene"] = a.scene;
    if (a.lod) report["lod"] = a.lod;
    report["device"] = ctx.info().name;
    report["decoder"] = std::string(seg::graph_use_name(graph_use)) +
                        (decoder ? " (" + decoder->name() + ")" : std::string());
    if (result.graph) {
        auto& g = *result.graph;
        report["graph"] = {{"solver", seg::graph_solver_name(g.solver)}, {"nodes", g.nodes},         {"seeds", g.seeds},         {"unreached", g.unreached}, {"unreached_components", g.unreached_components},
                           {"iterations", g.iterations}, {"levels", g.levels}, {"jacobi_retries", g.jacobi_retries}, {"range_retries", g.range_retries}, {"out_of_range", g.out_of_range}, {"rounds", g.rounds}, {"forest_free", g.forest_free}, {"widened_clicks", g.widened_clicks}, {"object_splits", g.object_splits}, {"residual", g.residual}, {"cell", g.cell},
                           {"spacing", g.spacing},     {"k", o.graph_options.k}, {"domain", g.domain}, {"stride", g.stride}, {"margin", g.margin}, {"focused", g.focused}};
    }
    report["failed"] = failed;
    report["gaussians"] = cloud.size();
    report["up"] = {o.up.x, o.up.y, o.up.z};
    report["lift"] = seg::lift_rule_name(o.lift);
    for (auto& obj : result.objects) {
        nlohmann::json jo{{"id", obj.id},          {"name", obj.name},       {"roi_gaussians", obj.roi_gaussians},
                          {"batches", obj.batches}, {"gaussians", obj.labelled}, {"sigma", obj.sigma},
                          {"roi", {obj.roi.length, obj.roi.width}}};
        if (graph_use != seg::GraphUse::None && obj.error.empty()) {
            jo["graph_roi_scale"] = obj.graph_scale, jo["boundary_contrast"] = obj.boundary_contrast;
            for (auto [scale, contrast, claimed] : obj.scale_answers)
                jo["roi_scales"].push_back({{"scale", scale}, {"boundary_contrast", contrast}, {"claimed", claimed}});
        }
        if (!obj.error.empty()) jo["error"] = obj.error;
        if (graph_use == seg::GraphUse::Unary) {
            jo["network_prior"] = obj.network_trusted;
            jo["network_answer"] = obj.network_answer;
        }
        // fallback: the click's pixel never reached tau (under --lift tau it lifted at tau x its final
        // opacity, coverage).
        for (auto& an : obj.anchors)
            jo["anchors"].push_back({{"position", {an.position.x, an.position.y, an.position.z}},
                                     {"positive", an.positive}, {"gaussian", an.gaussian},
                                     {"fallback", an.fallback}, {"coverage", an.coverage}});
        report["objects"].push_back(jo);
    }

    // 3D outputs: the scene with the labels, one standard 3DGS file per object.
    auto t0 = std::chrono::steady_clock::now();
    std::vector<seg::ExportObject> objects;
    for (auto& obj : result.objects)
        if (obj.error.empty()) objects.push_back({obj.id, obj.name});
    write_3d_outputs(ctx, a.export_format, cloud, result.labels, "instance", objects, stage, "objects");
    result.stage_ms["write 3D"] = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

    // 2D outputs: label rasterization and refinement on the GPU for every chosen view.
    if (!views.empty()) {
        seg::ViewExportOptions vo;
        vo.masks.mode = mode;
        vo.masks.refine = !a.no_refine;
        Progress progress("masks", views.size());
        vo.progress = [&](size_t, const std::string& view) {
            progress.step(view);
            return true;
        };
        for (auto& [name, ms] : seg::write_view_masks(ctx, scene, result.labels, cameras, views, stage, vo))
            result.stage_ms[name] += ms;
        progress.finish();
        report["views"] = views.size();
    }
    for (auto& [name, ms] : result.stage_ms) report["stage_ms"][name] = ms;
    report["total_ms"] = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - total_start).count();
    data::write_atomically(stage / "report.json", [&](std::ostream& os) { os << report.dump(2) << "\n"; });
    staged.commit();
    std::printf("segmented %zu object(s) (", result.objects.size() - failed);
    bool first = true;
    for (auto& obj : result.objects)
        if (obj.error.empty()) {
            std::printf("%s%s: %zu Gaussians", first ? "" : ", ", obj.name.c_str(), obj.labelled);
            first = false;
        }
    std::printf("), %zu view(s) of masks, into %s\n", views.size(), a.out.c_str());
    if (failed)
        throw PartialFailure(std::to_string(failed) + " of " + std::to_string(result.objects.size()) +
                             " object(s) failed (named above and in report.json); the others were written");
}

}  // namespace

void register_segment(CLI::App& app, std::function<void()>& run) {
    auto a = std::make_shared<SegmentArgs>();
    auto* cmd = app.add_subcommand("segment", "Segment objects from clicks: 3D labels, object PLYs, per-view masks");
    add_scene_option(*cmd, a->scene, a->lod);
    add_export_format_option(*cmd, a->export_format);
    cmd->add_option("--cameras", a->cameras, "Camera file or COLMAP folder")->required();
    cmd->add_option("--prompts", a->prompts, "prompts.json: objects and their clicks (required unless --semantic)");
    cmd->add_flag("--semantic", a->semantic, "No clicks: label every Gaussian by class with the semantic model (default: the shipped assets/models/semantic.safetensors; ground-truth reads the scene's 'class' property, an evaluation tool)");
    cmd->add_option("--tile", a->tile, "--semantic: tile side in scene units (default: the model's)");
    cmd->add_option("--out", a->out, "Output folder")->required();
    cmd->add_option("--model", a->model, "Decoder: a PTv3 model file (.safetensors; default: the shipped assets/models/interactive.safetensors), or ground-truth (evaluation tool reading the scene's labels)");
    cmd->add_option("--views", a->views, "Views to write masks for: all, none, or indices/names")->capture_default_str();
    cmd->add_option("--mode", a->mode, "Label projection: occlusion or paper")->capture_default_str();
    cmd->add_flag("--no-refine", a->no_refine, "Skip mask refinement");
    cmd->add_option("--up", a->up, "Up axis: cameras, ground, or x,y,z / -y ...")->capture_default_str();
    cmd->add_option("--scale", a->scale, "Typical object size (default: from the cameras)");
    cmd->add_option("--sigma", a->sigma, "Click weight fall-off in scene units (default: 0.4 x scale)");
    cmd->add_option("--roi", a->roi, "ROI length,width in scene units (default: 2.5 x scale each)");
    cmd->add_option("--label-property", a->label_property, "Property the ground-truth decoder reads")
        ->capture_default_str();
    cmd->add_option("--seed", a->seed, "Partition seed")->capture_default_str();
    cmd->add_option("--decoder", a->decoder, "ptv3, graph (random walk on the kNN graph, no network) or ptv3+graph (the network's probabilities as the walk's unary terms); default graph, or ptv3+graph when --model is given");
    cmd->add_flag("--strict", a->strict, "Any object that fails stops the run (exit 1, nothing written); by default it is left out, the others are written and the exit code is 2");
    cmd->add_option("--lift", a->lift, "Where a click in a view lands: surface (the pixel's dominant surface: what the masks show there) or tau (where the opacity first reaches 0.9, the paper's rule)")->capture_default_str();
    cmd->add_option("--graph-solver", a->solver, "Graph: walk (random-walk probabilities), forest (each Gaussian takes the label of the seed it reaches by the widest path) or walk+forest (the walk where it is sure, the forest for the rest)")->capture_default_str();
    cmd->add_option("--graph-k", a->graph.k, "Graph: neighbours per Gaussian (1-16)")->capture_default_str();
    cmd->add_option("--graph-colour", a->graph.colour, "Graph: colour contrast beta_c in exp(-beta_c |drgb|^2)")->capture_default_str();
    cmd->add_option("--graph-normal", a->graph.normal, "Graph: normal contrast beta_n")->capture_default_str();
    cmd->add_option("--graph-cell", a->graph.cell, "Graph: grid cell side in median nearest-neighbour distances (the neighbour search is exact within one cell side)")->capture_default_str();
    cmd->add_option("--graph-shells", a->graph.shells, "Graph: shells of grid cells a Gaussian short of k neighbours searches (1-4; more joins sparse Gaussians, and lets floaters bridge objects)")->capture_default_str();
    cmd->add_option("--graph-opacity", a->graph.opacity, "Graph: an edge's weight has the factor min(opacity)^this (0: opacity plays no part)")->capture_default_str();
    cmd->add_option("--graph-distance", a->graph.distance, "Graph: distance fall-off in local spacings")->capture_default_str();
    cmd->add_option("--graph-max-nodes", a->graph_max_nodes, "Graph: most nodes one graph holds (0: what the device's largest binding allows); a larger domain is solved on every n-th Gaussian, the rest labelled as their nearest solved one")->capture_default_str();
    cmd->add_option("--graph-budget", a->graph_budget, "Graph: a click's budget in nodes; past it the margin narrows to 0.1, then the larger --graph-scales are left out (before any decimation), so a click costs about what the ROIs at the smallest scale hold (0: no budget)")->capture_default_str();
    cmd->add_option("--graph-focus", a->graph_focus, "Graph: past this many nodes a domain is first solved on every (2 x --walk-coarse)-th node; the fine graph then covers the box of what each object's coarse walk reaches (grown by a quarter per side) and the same margin around it, so a click's cost follows the object, not the scene (0: never)")->capture_default_str();
    cmd->add_option("--graph-margin", a->margin, "Graph: the solve's domain is the largest scaled ROIs widened by this fraction per side; what lies in the margin seeds the background")->capture_default_str();
    cmd->add_option("--graph-scales", a->scales, "Graph: the background's boundary at each object's ROI scaled by each of these, one solve each; per object the smallest scale's answer stands unless a larger one's boundary contrast is below --graph-scale-ratio times its own; ptv3+graph then solves the largest once more with the network's prior, whose answer stands per object where its boundary contrast is no higher than the chosen one's (or below --unary-clean where the chosen one's is 0)")->delimiter(',')->capture_default_str();
    cmd->add_option("--graph-scale-ratio", a->scale_ratio, "Graph: how much weaker (mean cut edge weight over mean inside edge weight) a larger ROI's boundary must be to win")->capture_default_str();
    cmd->add_option("--unary", a->unary, "ptv3+graph: strength of the network's probabilities, in units of a Gaussian's degree")->capture_default_str();
    cmd->add_option("--unary-confidence", a->unary_confidence, "ptv3+graph: the network's probabilities count only where its most likely label reaches this")->capture_default_str();
    cmd->add_option("--unary-clean", a->unary_clean,
                    "ptv3+graph: where the graph alone's answer cuts no edge (whole graph components), the network's answer stands if its boundary contrast is below this (0: never there)")
        ->capture_default_str()
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--walk-iterations", a->walk.max_iterations, "Graph: most conjugate-gradient iterations")->capture_default_str();
    cmd->add_option("--walk-dense-labels", a->walk.dense_labels, "Graph: up to this many labels (objects + background) every node keeps every label's value; past it each node keeps its 16 largest (same labels, flat memory)")->capture_default_str();
    cmd->add_option("--walk-coarse", a->coarse, "Graph: a first solve on every n-th Gaussian (1: none): the viewer's early answer, and where a Jacobi-preconditioned solve starts (multigrid starts from the prior)")->capture_default_str();
    cmd->add_option("--walk-sure", a->walk_sure, "walk+forest: the walk's label stands where its share of the probability reaches this")->capture_default_str();
    cmd->add_option("--object-split-clean", a->splits.clean, "walk+forest: where two objects meet, the widest paths' split from the clicks replaces the walk's if its edges are on average below this share of the objects' inner edges (0: never)")->capture_default_str()->check(CLI::Range(0.0, 1.0));
    cmd->add_option("--object-split-ratio", a->splits.ratio, "walk+forest: ... and below this share of the walk's split's")->capture_default_str()->check(CLI::Range(0.0, 1.0));
    cmd->add_option("--walk-tolerance", a->walk.tolerance, "Graph: relative residual to stop at")->capture_default_str();
    cmd->add_option("--walk-preconditioner", a->preconditioner, "Graph: the conjugate gradient's preconditioner: multigrid (an aggregation V-cycle) or jacobi (the diagonal)")->capture_default_str();
    cmd->add_option("--walk-coarse-scale", a->walk.coarse_scale, "Graph, multigrid: the coarse correction's scale")->capture_default_str();
    add_device_option(*cmd, a->device);
    add_memory_option(*cmd, a->device);
    // Option conflicts are reported when the command runs (main's error handling), not while parsing.
    cmd->callback([a, cmd, &run] {
        std::string click_flag;
        for (const char* flag : {"--decoder", "--sigma", "--roi", "--scale", "--strict", "--lift"})
            if (cmd->count(flag) && click_flag.empty()) click_flag = flag;
        const bool tile = cmd->count("--tile") > 0;
        run = [a, click_flag, tile] {
            if (!a->semantic) {
                if (a->prompts.empty())
                    throw data::InputError("--prompts", "is required (objects and their clicks), unless --semantic");
                if (tile) throw data::InputError("--tile", "applies to --semantic only");
                return run_segment(*a);
            }
            if (!a->prompts.empty())
                throw data::InputError("--prompts", "the semantic mode takes no clicks (drop --prompts or --semantic)");
            if (!click_flag.empty()) throw data::InputError(click_flag, "applies to clicks, not to --semantic");
            SemanticSegmentArgs s;
            s.scene = a->scene, s.cameras = a->cameras, s.out = a->out, s.model = a->model, s.views = a->views;
            s.mode = a->mode, s.up = a->up, s.tile = a->tile, s.seed = a->seed, s.device = a->device, s.lod = a->lod;
            s.export_format = a->export_format;
            run_segment_semantic(s);
        };
    });
}

}  // namespace pg::app

#include "app/viewer/job_engine.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app/common/ptv3_classifier.h"
#include "app/common/ptv3_decoder.h"
#include "app/common/staged_output.h"
#include "dataset/atomic_file.h"
#include "dataset/error.h"
#include "dataset/formats/camera_io.h"
#include "dataset/formats/scene_io.h"
#include "engine/compress/sog_quantizer.h"
#include "engine/segment/export.h"
#include "engine/segment/prompt_encoder.h"
#include "engine/segment/warm_up.h"
#include "engine/vk/context.h"

namespace pg::viewer {

namespace fs = std::filesystem;

JobEngine::JobEngine(vk::Context& ctx, const SceneData& scene, const render::GpuScene& gpu_scene)
    : ctx_(ctx), scene_(scene), gpu_scene_(gpu_scene), lift_renderer_(ctx) {}

void JobEngine::warm_up(const std::string& decoder) {
    seg::warm_up(ctx_, scene_.options);
    // The network, if the decoder has one, loads here too; a file that does not load says so on
    // the first click, as it did before.
    try {
        segmenter(network_for(decoder)).index_columns(scene_.options.up);
    } catch (const data::InputError&) {
    }
}

std::string JobEngine::network_for(const std::string& decoder) const {
    return decoder == "ground-truth" ? "ground-truth" : decoder == "graph" ? std::string() : scene_.model;
}

seg::Anchor JobEngine::lift(const data::Camera& camera, double u, double v, bool positive) {
    return seg::lift_click(lift_renderer_, gpu_scene_, camera, u, v, positive, scene_.options.render,
                           scene_.options.lift, "click", &lift_bins_);
}

seg::Anchor JobEngine::anchor(const data::PromptClick& click) {
    if (click.point) return seg::anchor_at_point(scene_.cloud, *click.point, click.positive);
    auto it = std::find_if(scene_.cameras.begin(), scene_.cameras.end(), [&](auto& c) { return c.name == click.view; });
    if (it == scene_.cameras.end()) throw data::InputError("click", "no camera named '" + click.view + "'");
    return lift(*it, click.u, click.v, click.positive);
}

seg::Segmenter& JobEngine::segmenter(const std::string& network) {
    auto& s = segmenters_[network];
    if (!s && network.empty()) s = std::make_unique<seg::Segmenter>(ctx_, scene_.cloud, gpu_scene_, scene_.cameras);
    if (!s) {
        std::unique_ptr<seg::Decoder> d;
        if (network == "ground-truth") {
            auto labels = scene_.cloud.int_property("instance");
            if (!labels) throw data::InputError(scene_.scene_path, "has no 'instance' property for the ground-truth decoder");
            d = std::make_unique<seg::GroundTruthDecoder>(*labels);
        } else {
            d = std::make_unique<app::Ptv3Decoder>(ctx_, network, &scene_.cloud);
        }
        decoders_[network] = std::move(d);
        s = std::make_unique<seg::Segmenter>(ctx_, scene_.cloud, gpu_scene_, scene_.cameras, *decoders_[network]);
    }
    return *s;
}

SegmentOutcome JobEngine::segment(const SegmentJob& job, std::map<std::string, double>& stage_ms,
                                  const std::atomic<bool>* cancel, const std::function<void(SegmentOutcome)>& coarse) {
    return segment_job(segmenter(network_for(job.decoder)), job, scene_.options, stage_ms, cancel, coarse);
}

ClassLabels JobEngine::label_by_class(const std::string& model, const std::atomic<bool>* cancel,
                                      const std::function<void(size_t, size_t)>& progress,
                                      std::map<std::string, double>& stage_ms) {
    if (model.empty())
        throw data::InputError("--semantic-model", "the shipped model assets/models/semantic.safetensors was not found "
                                                   "(set PG_SEMANTIC_MODEL or give --semantic-model FILE.safetensors)");
    if (!fs::exists(model)) throw data::InputError("--semantic-model", "'" + model + "' does not exist");
    if (model != classifier_path_ || !classifier_) {
        classifier_.reset();
        classifier_path_.clear();
        auto network = std::make_unique<app::Ptv3ClassNetwork>(ctx_, model, "--semantic-model");
        class_names_ = network->config().class_names;
        classifier_ = std::move(network);
        classifier_path_ = model;
    }
    seg::SemanticLabelOptions o;
    o.up = scene_.options.up;
    o.seed = scene_.options.seed;
    o.cancel = cancel;
    o.progress = progress;
    seg::SemanticLabels labels = seg::label_by_class(scene_.cloud, *classifier_, o);
    stage_ms = labels.stage_ms;
    ClassLabels out;
    out.model = model;
    out.names = class_names_;
    out.names.resize(size_t(classifier_->classes()));
    for (size_t c = 0; c < out.names.size(); ++c)
        if (out.names[c].empty()) out.names[c] = "class_" + std::to_string(c);
    out.classes = std::move(labels.classes);
    out.confidence = std::move(labels.confidence);
    out.counts = std::move(labels.class_counts);
    return out;
}

void JobEngine::write(const ExportRequest& rq, std::atomic<size_t>& done, std::atomic<size_t>& total,
                      const std::atomic<bool>& cancel) {
    const fs::path out = rq.folder;
    // Written into a staging folder and moved into `out` only when whole, as segment does: a
    // failure or a cancel part-way leaves `out` as it was.
    app::StagedOutput staged(out);
    const fs::path dir = staged.dir();
    std::vector<fs::path> inputs{scene_.scene_path};
    if (!scene_.cameras_path.empty()) inputs.push_back(scene_.cameras_path);
    // Without objects (class labels alone) the object outputs are left out.
    static const std::vector<int32_t> no_labels;
    const auto& labels = rq.labels ? *rq.labels : no_labels;
    const bool objects_labelled = rq.labels != nullptr;
    std::vector<seg::ExportObject> objects;
    std::map<int, glm::vec3> colours;
    for (auto& o : rq.document.objects) {
        objects.push_back({o.id, o.name});
        colours[o.id] = o.colour;
    }
    const bool sog = rq.format == "sog";
    const seg::CloudWriter write_sog = sog ? compress::gpu_sog_writer(ctx_) : nullptr;
    if (rq.scene && sog) {
        // SOG holds no labels: the scene as it was loaded, for the web viewers.
        seg::refuse_overwriting(out / "scene.sog", inputs);
        write_sog(scene_.cloud, dir / "scene.sog");
    } else if (rq.scene) {
        seg::refuse_overwriting(out / "scene.ply", inputs);
        if (rq.classes && objects_labelled) {
            // Both properties in one file (one copy of the scene, not write_labelled_scene's two):
            // `instance` as a segment export has it, and `class` as segment --semantic writes it.
            data::GaussianCloud labelled = scene_.cloud;
            labelled.set_int_property("instance", labels);
            labelled.set_int_property("class", rq.classes->classes);
            data::write_ply(labelled, dir / "scene.ply");
        } else if (rq.classes) {
            seg::write_labelled_scene(scene_.cloud, rq.classes->classes, dir / "scene.ply", "class");
        } else {
            seg::write_labelled_scene(scene_.cloud, labels, dir / "scene.ply");
        }
    }
    if (rq.objects && objects_labelled)
        seg::write_object_files(scene_.cloud, labels, objects, dir / "objects", write_sog,
                                sog ? ".sog" : ".ply");
    if (rq.prompts) {
        data::write_prompts(rq.prompts_json, dir / "prompts.json");
        if (scene_.cameras_path.empty()) data::write_inria_cameras_json(scene_.cameras, dir / "cameras.json");
    }
    std::map<std::string, double> mask_ms;
    if (rq.masks && objects_labelled && !scene_.cameras.empty()) {
        std::vector<size_t> views(scene_.cameras.size());
        for (size_t i = 0; i < views.size(); ++i) views[i] = i;
        total = views.size();
        seg::ViewExportOptions vo;
        vo.colour = [&](uint32_t l) { return colours.count(int(l)) ? colours[int(l)] : seg::ViewMask::default_colour(l); };
        vo.progress = [&](size_t n, const std::string&) {
            done = n;
            return !cancel.load();
        };
        mask_ms = seg::write_view_masks(ctx_, gpu_scene_, labels, scene_.cameras, views, dir, vo);
    }
    if (cancel.load()) return;  // the staging folder goes with `staged`: nothing lands in `out`

    // What `pointgauss segment` needs to replay the prompts exactly.
    const glm::dvec3 up = scene_.options.up;
    char up_arg[128];
    std::snprintf(up_arg, sizeof up_arg, "%.17g,%.17g,%.17g", up.x, up.y, up.z);
    const std::string cameras = scene_.cameras_path.empty() ? (out / "cameras.json").string() : scene_.cameras_path;
    std::ostringstream replay;
    replay << "pointgauss segment " << scene_.scene_path << (scene_.lod ? " --lod " + std::to_string(scene_.lod) : "")
           << " --cameras " << cameras << " --prompts "
           << (out / "prompts.json").string() << " --up " << up_arg << " --lift " << seg::lift_rule_name(scene_.options.lift);
    if (rq.decoder == "ground-truth") replay << " --model ground-truth --decoder ptv3";
    else if (rq.decoder == "graph") replay << " --decoder graph";
    else replay << " --model " << scene_.model << " --decoder " << rq.decoder;
    replay << " --out OUT";
    nlohmann::json report;
    report["scene"] = scene_.scene_path;
    report["cameras"] = cameras;
    report["device"] = ctx_.info().name;
    report["decoder"] = rq.decoder;
    report["gaussians"] = scene_.cloud.size();
    report["up"] = {up.x, up.y, up.z};
    report["replay"] = replay.str();
    for (auto& o : rq.document.objects) {
        size_t n = 0;
        for (int32_t l : labels) n += l == o.id;
        report["objects"].push_back({{"id", o.id},
                                     {"name", o.name},
                                     {"gaussians", n},
                                     {"colour", {o.colour.r, o.colour.g, o.colour.b}},
                                     {"hidden", o.hidden}});
        // Made from a class region: not in prompts.json, since its clicks alone do not make it.
        if (o.region) report["objects"].back()["from"] = o.region->source;
    }
    if (rq.classes) {
        report["semantic_model"] = rq.classes->model;
        for (size_t c = 0; c < rq.classes->counts.size(); ++c)
            report["classes"].push_back(
                {{"id", c}, {"name", rq.classes->name(int(c))}, {"gaussians", rq.classes->counts[c]}});
    }
    for (auto& [name, ms] : rq.stage_ms) report["stage_ms"][name] = ms;
    for (auto& [name, ms] : mask_ms) report["stage_ms"][name] = ms;
    data::write_atomically(dir / "report.json", [&](std::ostream& os) { os << report.dump(2) << "\n"; });
    staged.commit();
}

}  // namespace pg::viewer

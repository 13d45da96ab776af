// pointgauss train --data DIR... --config tiny|small|paper|FILE --out MODEL.safetensors:
// trains the interactive PTv3 on labelled scenes (dataset/train: first click, ROI, partition
// batch, click weights, augmentation) or, on semantic suites, the semantic one (tile columns,
// appearance features, classes). The run itself is nn/train/training_run.h; this reads the
// options, loads the scenes, sets up the trainer (fresh or from --resume) and prints progress.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <optional>

#include <unistd.h>

#include "app/cli/commands.h"
#include "app/common/ptv3_decoder.h"
#include "dataset/error.h"
#include "dataset/eval/suite_info.h"
#include "dataset/semantic/gaussian_features.h"
#include "dataset/train/semantic_drawer.h"
#include "dataset/train/sample_drawer.h"
#include "dataset/train/train_scene.h"
#include "engine/vk/context.h"
#include "nn/safetensors.h"
#include "nn/train/checkpoint.h"
#include "nn/train/initial_weights.h"
#include "nn/train/trainer.h"
#include "nn/train/training_run.h"

namespace pg::app {

namespace {

struct TrainArgs {
    std::vector<std::string> data, val;
    std::string config = "tiny", out, resume, init, task = "auto", features = "none";
    int points = 8192;
    double tile = 64.0, grid = 0.01;
    double weight_decay = 0.05, drop_path = 0.1, lovasz = 0;
    nn::train::RunOptions run;  // out is set from `out`
    DeviceOptions device;
};

std::vector<data::train::TrainScene> load_scenes(const std::vector<std::string>& dirs, const std::string& split,
                                                 const char* what, const std::vector<std::string>& feature_groups) {
    std::vector<std::filesystem::path> paths(dirs.begin(), dirs.end());
    std::vector<data::train::TrainScene> scenes;
    for (const auto& p : data::train::find_train_scenes(paths, split))
        scenes.push_back(data::train::load_train_scene(p, std::nullopt, feature_groups));
    if (scenes.empty()) throw data::InputError(what, "holds no " + split + " scenes");
    return scenes;
}

// --features: none, all, or a comma-separated list of semantic/gaussian_features.h groups.
std::vector<std::string> feature_groups_arg(const std::string& arg) {
    if (arg == "none") return {};
    if (arg == "all") return data::semantic::all_feature_groups();
    std::vector<std::string> groups;
    size_t start = 0;
    while (start <= arg.size()) {
        const size_t comma = std::min(arg.find(',', start), arg.size());
        groups.push_back(arg.substr(start, comma - start));
        start = comma + 1;
    }
    try {
        data::semantic::feature_channels(groups);
    } catch (const std::invalid_argument& e) {
        throw data::InputError("--features", e.what());
    }
    return groups;
}

// The task the data asks for: semantic when every --data path is a semantic suite.
bool semantic_data(const std::vector<std::string>& dirs) {
    bool any = false, all = true;
    for (const auto& d : dirs) {
        const bool suite = std::filesystem::exists(std::filesystem::path(d) / "suite.json");
        const bool sem = suite && data::eval::read_suite_json(d).semantic();
        any = any || sem;
        all = all && sem;
    }
    if (any && !all) throw data::InputError("--data", "mixes semantic suites with instance data");
    return any;
}

// Class names from the suites' suite.json (all must agree): the model's classes.
std::vector<std::string> suite_class_names(const std::vector<std::string>& dirs, const char* what) {
    std::vector<std::string> names;
    for (const auto& d : dirs) {
        if (!std::filesystem::exists(std::filesystem::path(d) / "suite.json"))
            throw data::InputError(what, "'" + d + "' is not a suite folder: the semantic task reads classes from suite.json");
        const auto suite = data::eval::read_suite_json(d);
        if (!suite.semantic()) throw data::InputError(what, "'" + d + "' is an instance suite, not a semantic one");
        std::vector<std::string> these;
        for (const auto& c : suite.classes) {
            if (c.id != int32_t(these.size()))
                throw data::InputError(d + "/suite.json", "class ids must be 0, 1, 2, ... in order");
            these.push_back(c.name);
        }
        if (!names.empty() && these != names)
            throw data::InputError(what, "'" + d + "' has other classes than the first suite");
        names = these;
    }
    return names;
}

std::unique_ptr<data::train::SemanticDrawer> semantic_drawer(const std::vector<std::string>& dirs,
                                                             const std::string& split, const char* what,
                                                             const nn::Ptv3Config& config,
                                                             const data::train::SemanticOptions& options) {
    if (suite_class_names(dirs, what) != config.class_names)
        throw data::InputError(what, "its classes differ from the model's");
    std::vector<std::filesystem::path> paths(dirs.begin(), dirs.end());
    std::vector<data::train::SemanticScene> scenes;
    for (const auto& p : data::train::find_train_scenes(paths, split)) {
        std::fprintf(stderr, "loading %s\n", p.string().c_str());
        scenes.push_back(data::train::load_semantic_scene(p, options));
    }
    if (scenes.empty()) throw data::InputError(what, "holds no " + split + " scenes");
    return std::make_unique<data::train::SemanticDrawer>(std::move(scenes), config.num_classes, options);
}

void run_train(const TrainArgs& a) {
    if (a.run.steps < 1) throw data::InputError("--steps", "must be at least 1");
    if (a.run.batch < 1) throw data::InputError("--batch", "must be at least 1");
    if (a.points < 64) throw data::InputError("--points", "must be at least 64");
    if (a.run.stop_at < 0) throw data::InputError("--stop-at", "must be 0 or more");
    if (a.run.max_clicks < 0) throw data::InputError("--clicks", "must be 0 or more");
    if (!(a.run.lr > 0)) throw data::InputError("--lr", "must be positive");
    if (!(a.drop_path >= 0 && a.drop_path < 1)) throw data::InputError("--drop-path", "must be in [0, 1)");
    if (!(a.lovasz >= 0 && a.lovasz <= 100)) throw data::InputError("--lovasz", "must be in [0, 100]");
    if (std::filesystem::path(a.out).extension() != ".safetensors")
        throw data::InputError("--out", "must end in .safetensors");
    for (const auto& d : a.data)
        if (std::filesystem::weakly_canonical(d) == std::filesystem::weakly_canonical(a.out))
            throw data::InputError("--out", "would overwrite an input");

    // Config and starting point: a checkpoint to resume, a config name, or a model file's config.
    std::unique_ptr<nn::train::Checkpoint> ckpt;
    nn::Ptv3Config config;
    if (!a.resume.empty()) {
        try {
            ckpt = std::make_unique<nn::train::Checkpoint>(nn::train::load_checkpoint(a.resume));
        } catch (const nn::FormatError& e) {
            throw data::InputError("--resume", e.what());
        }
        config = ckpt->config;
    }
    // --init: a model file's weights and config, with a fresh optimizer and schedule (fine-tuning).
    std::map<std::string, std::vector<float>> init_values;
    if (!a.init.empty()) {
        if (ckpt) throw data::InputError("--init", "cannot be combined with --resume (a checkpoint holds its own weights)");
        try {
            const nn::SafeTensors file = nn::SafeTensors::load(a.init);
            config = nn::Ptv3Weights::config_of(file);
            init_values = nn::Ptv3Weights::host_values(file);
        } catch (const nn::FormatError& e) {
            throw data::InputError("--init", e.what());
        }
    }
    const bool from_model = ckpt || !a.init.empty();
    const char* start_option = ckpt ? "--resume" : !a.init.empty() ? "--init" : "--config";
    if (a.task != "auto" && a.task != "interactive" && a.task != "semantic")
        throw data::InputError("--task", "expected auto, interactive or semantic, got '" + a.task + "'");
    const bool semantic = a.task == "auto" ? (from_model ? config.semantic() : semantic_data(a.data)) : a.task == "semantic";
    if (!from_model) {
        config = ptv3_config_arg(a.config, "--config");
        if (semantic) {
            if (!(a.tile > 0)) throw data::InputError("--tile", "must be positive");
            if (!(a.grid > 0 && a.grid < 1)) throw data::InputError("--grid", "must be in (0, 1)");
            config.features = data::semantic::all_feature_groups();
            config.in_channels = data::semantic::feature_channels(config.features);
            config.class_names = suite_class_names(a.data, "--data");
            config.num_classes = int(config.class_names.size());
            config.input_frame = "tile";
            config.tile_size = a.tile;
            config.grid_size = a.grid;
        } else {
            config.features = feature_groups_arg(a.features);
            config.in_channels = 2 + data::semantic::feature_channels(config.features);
            config.num_classes = 2;
            config.input_frame = "roi";
        }
    }
    const bool fits = semantic ? config.semantic()
                               : !config.semantic() && config.input_frame == "roi" && config.num_classes == 2 &&
                                     config.in_channels == 2 + data::semantic::feature_channels(config.features);
    if (!fits)
        throw data::InputError(start_option, semantic ? "is not a semantic model" : "is not an interactive model");

    std::unique_ptr<data::train::SampleDrawer> drawer, val_drawer;
    std::unique_ptr<data::train::SemanticDrawer> sem_drawer, sem_val;
    std::unique_ptr<nn::train::TrainingTask> task;
    if (semantic) {
        data::train::SemanticOptions so;
        so.max_points = uint32_t(a.points);
        so.tile = config.tile_size;
        so.grid = config.grid_size;
        so.features = config.features;
        if (data::semantic::feature_channels(so.features) != config.in_channels)
            throw data::InputError(start_option, "its feature groups do not give its in_channels");
        sem_drawer = semantic_drawer(a.data, "train", "--data", config, so);
        if (!a.val.empty()) sem_val = semantic_drawer(a.val, "test", "--val", config, so.without_augmentation());
        std::fprintf(stderr, "training the semantic model (%d classes) on %zu scene(s); validation on %zu scene(s)\n",
                     config.num_classes, sem_drawer->scenes().size(), sem_val ? sem_val->scenes().size() : size_t(0));
        task = std::make_unique<nn::train::SemanticTask>(*sem_drawer, sem_val.get());
    } else {
        data::train::SampleOptions so;
        so.max_points = uint32_t(a.points);
        so.features = config.features;
        so.voxel = config.grid_size;
        so.scale_spacing = config.scale_spacing;
        drawer = std::make_unique<data::train::SampleDrawer>(load_scenes(a.data, "train", "--data", so.features), so);
        if (!a.val.empty())
            val_drawer = std::make_unique<data::train::SampleDrawer>(load_scenes(a.val, "test", "--val", so.features),
                                                                     so.without_augmentation());
        std::fprintf(stderr, "training on %zu scene(s), %zu objects; validation on %zu scene(s)\n",
                     drawer->scenes().size(), drawer->object_count(), val_drawer ? val_drawer->scenes().size() : size_t(0));
        task = std::make_unique<nn::train::InteractiveTask>(*drawer, val_drawer.get());
    }

    vk::ContextOptions co;
    co.device = a.device.device;
    vk::Context ctx(co);
    auto pool = nn::Pool::create(ctx);
    nn::train::TrainOptions to;
    to.drop_path = a.drop_path;
    to.lovasz_weight = a.lovasz;
    to.seed = a.run.seed;
    to.adamw.weight_decay = a.weight_decay;
    auto weights = ckpt ? nn::Ptv3Weights::from_host(*pool, config, ckpt->weights, a.resume)
                   : !a.init.empty() ? nn::Ptv3Weights::from_host(*pool, config, init_values, a.init)
                                     : nn::Ptv3Weights::from_host(*pool, config, nn::train::initial_weights(config, a.run.seed), "initial");
    init_values.clear();
    nn::train::Trainer trainer(*pool, std::move(weights), to);
    int64_t start = 0;
    if (ckpt) {
        nn::train::restore_optimizer(trainer, *ckpt);
        start = ckpt->step;
        ckpt.reset();
    }

    nn::train::RunOptions ro = a.run;
    ro.out = a.out;
    const bool tty = isatty(2) && !std::getenv("CI");
    auto report = [&](const nn::train::StepReport& p) {
        const long long step = (long long)p.step;
        const int steps = a.run.steps;
        if (p.validation)
            std::fprintf(stderr, "%sstep %lld: loss %.4f, accuracy %.3f, validation %s\n", tty ? "\r\x1b[K" : "", step,
                         p.loss, p.accuracy, p.validation->text().c_str());
        if (tty)
            std::fprintf(stderr, "\rstep %lld/%d  loss %.4f  acc %.3f  %.2f steps/s  eta %.0f min\x1b[K", step, steps,
                         p.loss, p.accuracy, p.steps_per_s, double(steps - step) / p.steps_per_s / 60.0);
        else if (step % 50 == 0)
            std::fprintf(stderr, "step %lld/%d loss %.4f acc %.3f %.2f steps/s\n", step, steps, p.loss, p.accuracy,
                         p.steps_per_s);
    };
    const nn::train::RunResult r = nn::train::run_training(trainer, start, *task, ro, report);
    if (tty) std::fprintf(stderr, "\n");
    if (!r.finished) {
        std::printf("stopped after step %lld of %d: resume with --resume %s\n", (long long)r.steps, a.run.steps,
                    r.checkpoint.string().c_str());
        return;
    }
    std::printf("wrote %s (%lld parameters) after %d steps in %.1f min on %s", a.out.c_str(),
                trainer.weights().parameter_count(), a.run.steps, r.seconds / 60.0, ctx.info().name.c_str());
    if (r.validation) std::printf("; validation %s", r.validation->text().c_str());
    std::printf("\n");
}

}  // namespace

void register_train(CLI::App& app, std::function<void()>& run) {
    auto a = std::make_shared<TrainArgs>();
    auto* cmd = app.add_subcommand("train", "Train the interactive or the semantic PTv3 on labelled scenes");
    cmd->add_option("--data", a->data, "Training scenes: suite folders (their train split), scene folders or PLYs with 'instance'")
        ->required();
    cmd->add_option("--task", a->task, "auto (semantic on semantic suites such as campus, else interactive), interactive or semantic")
        ->capture_default_str();
    cmd->add_option("--tile", a->tile, "Semantic: tile side in scene units (the scene is covered by columns this wide)")
        ->capture_default_str();
    cmd->add_option("--grid", a->grid, "Semantic: voxel side in tiles")->capture_default_str();
    cmd->add_option("--features", a->features,
                    "Interactive: per-Gaussian inputs after the click weights: none, all, or groups rgb,opacity,log_scale,"
                    "verticality (a resumed checkpoint keeps its own)")
        ->capture_default_str();
    cmd->add_option("--val", a->val, "Validation scenes: suite folders (their test split), scene folders or PLYs");
    cmd->add_option("--config", a->config, "tiny, small, paper, or a model file whose config to use")->capture_default_str();
    cmd->add_option("--out", a->out, "Model file to write (.safetensors); OUT.ckpt.safetensors and OUT.log.jsonl beside it")
        ->required();
    cmd->add_option("--steps", a->run.steps, "Optimizer steps in all (the schedule's length)")->capture_default_str();
    cmd->add_option("--batch", a->run.batch, "Samples (clouds) per step")->capture_default_str();
    cmd->add_option("--points", a->points, "N_max: points per sample")->capture_default_str();
    cmd->add_option("--clicks", a->run.max_clicks, "Most later clicks simulated on the model's errors per sample")
        ->capture_default_str();
    cmd->add_option("--lr", a->run.lr, "Peak learning rate (OneCycle)")->capture_default_str();
    cmd->add_option("--weight-decay", a->weight_decay, "AdamW weight decay")->capture_default_str();
    cmd->add_option("--drop-path", a->drop_path, "Drop path rate of the deepest block")->capture_default_str();
    cmd->add_option("--lovasz", a->lovasz, "Weight of a Lovasz-softmax loss added to the cross-entropy (0: off)")
        ->capture_default_str();
    cmd->add_option("--seed", a->run.seed, "Seed of weights, samples and drop path")->capture_default_str();
    cmd->add_option("--val-every", a->run.val_every, "Validate every N steps")->capture_default_str();
    cmd->add_option("--val-samples", a->run.val_samples, "Fixed validation samples")->capture_default_str();
    cmd->add_option("--checkpoint-every", a->run.checkpoint_every, "Write the checkpoint every N steps")->capture_default_str();
    cmd->add_option("--calibration", a->run.calibration, "Samples that settle the BatchNorm statistics at the end")
        ->capture_default_str();
    cmd->add_option("--resume", a->resume, "Continue from this checkpoint (OUT.ckpt.safetensors)");
    cmd->add_option("--init", a->init, "Start from this model file's weights and config, with a fresh optimizer and schedule (fine-tuning; the classes must be --data's)");
    cmd->add_option("--stop-at", a->run.stop_at, "Stop after this step, writing the checkpoint only (train in chunks)");
    add_device_option(*cmd, a->device);
    cmd->callback([a, &run] { run = [a] { run_train(*a); }; });
}

}  // namespace pg::app

// pointgauss train --data DIR... --config tiny|small|paper|FILE --out MODEL.safetensors:
// trains the interactive PTv3 on labelled scenes (dataset/train: first click, ROI, partition
// batch, click weights, augmentation; later clicks on the model's own errors), with AdamW and
// the OneCycle schedule, validation on held-out scenes, checkpoints and resume. Seeded: every
// step's samples and drop-path masks derive from (seed, step), so a resumed run draws what the
// uninterrupted one would have.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>

#include <nlohmann/json.hpp>

#include "app/cli/commands.h"
#include "app/cli/train_curves.h"
#include "app/common/ptv3_decoder.h"
#include "dataset/atomic_file.h"
#include "dataset/clicks/mask.h"
#include "dataset/error.h"
#include "dataset/random.h"
#include "dataset/train/sample_drawer.h"
#include "dataset/train/train_scene.h"
#include "engine/vk/context.h"
#include "nn/safetensors.h"
#include "nn/train/checkpoint.h"
#include "nn/train/initial_weights.h"
#include "nn/train/trainer.h"

namespace pg::app {

namespace {

struct TrainArgs {
    std::vector<std::string> data, val;
    std::string config = "tiny", out, resume;
    int steps = 2000, batch = 2, points = 8192, max_clicks = 3, val_every = 100, val_samples = 24,
        checkpoint_every = 100, calibration = 32, stop_at = 0;
    double lr = 0.002, weight_decay = 0.05, drop_path = 0.1, lovasz = 0;
    uint64_t seed = 1;
    DeviceOptions device;
};

uint64_t step_seed(uint64_t seed, int64_t step, uint64_t stream) {
    return seed * 0x9E3779B97F4A7C15ull + uint64_t(step) * 0xD1B54A32D192ED03ull + stream;
}

std::vector<data::train::TrainScene> load_scenes(const std::vector<std::string>& dirs, const std::string& split,
                                                 const char* what) {
    std::vector<std::filesystem::path> paths(dirs.begin(), dirs.end());
    std::vector<data::train::TrainScene> scenes;
    for (const auto& p : data::train::find_train_scenes(paths, split)) scenes.push_back(data::train::load_train_scene(p));
    if (scenes.empty()) throw data::InputError(what, "holds no " + split + " scenes");
    return scenes;
}

nn::Ptv3Input batch_input(const std::vector<data::train::Sample>& samples, std::vector<int32_t>& labels) {
    nn::Ptv3Input in;
    labels.clear();
    for (const auto& s : samples) {
        in.coord.insert(in.coord.end(), s.coord.begin(), s.coord.end());
        in.feat.insert(in.feat.end(), s.feat.begin(), s.feat.end());
        labels.insert(labels.end(), s.labels.begin(), s.labels.end());
        in.offsets.push_back(int64_t(in.size()));
    }
    return in;
}

nn::Ptv3Input sample_input(const data::train::Sample& s) {
    nn::Ptv3Input in;
    in.coord = s.coord;
    in.feat = s.feat;
    return in;
}

std::vector<uint8_t> predict(nn::Ptv3& model, const data::train::Sample& s) {
    const auto out = model.forward(sample_input(s));
    std::vector<uint8_t> mask(s.size());
    for (size_t i = 0; i < s.size(); ++i) mask[i] = out.logits[2 * i + 1] > out.logits[2 * i];
    return mask;
}

struct Validation {
    double iou1 = 0, iou3 = 0;  // mean IoU after the first click and after two more
};

// Mean IoU over fixed held-out samples, inference mode (running statistics), as the pipeline runs it.
Validation validate(nn::Pool& pool, const nn::Ptv3Weights& weights, const data::train::SampleDrawer& drawer,
                    std::vector<data::train::Sample> samples) {
    nn::Ptv3 model(pool, weights);
    Validation v;
    for (auto& s : samples) {
        const data::clicks::Mask object = data::clicks::mask_of(s.labels, 1);
        auto pred = predict(model, s);
        v.iou1 += data::clicks::iou(object, pred);
        for (int k = 0; k < 2 && drawer.add_click(s, pred); ++k) pred = predict(model, s);
        v.iou3 += data::clicks::iou(object, pred);
    }
    v.iou1 /= double(std::max<size_t>(samples.size(), 1));
    v.iou3 /= double(std::max<size_t>(samples.size(), 1));
    return v;
}

void run_train(const TrainArgs& a) {
    if (a.steps < 1) throw data::InputError("--steps", "must be at least 1");
    if (a.batch < 1) throw data::InputError("--batch", "must be at least 1");
    if (a.points < 64) throw data::InputError("--points", "must be at least 64");
    if (a.stop_at < 0) throw data::InputError("--stop-at", "must be 0 or more");
    if (a.max_clicks < 0) throw data::InputError("--clicks", "must be 0 or more");
    if (!(a.lr > 0)) throw data::InputError("--lr", "must be positive");
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
    } else {
        config = ptv3_config_arg(a.config, "--config");
        config.in_channels = 2;
        config.num_classes = 2;
        config.input_frame = "roi";
    }
    if (config.input_frame != "roi" || config.in_channels != 2 || config.num_classes != 2)
        throw data::InputError("--resume", "is not an interactive model checkpoint");

    data::train::SampleOptions so;
    so.max_points = uint32_t(a.points);
    const data::train::SampleDrawer drawer(load_scenes(a.data, "train", "--data"), so);
    std::unique_ptr<data::train::SampleDrawer> val_drawer;
    if (!a.val.empty())
        val_drawer = std::make_unique<data::train::SampleDrawer>(load_scenes(a.val, "test", "--val"),
                                                                 so.without_augmentation());
    std::fprintf(stderr, "training on %zu scene(s), %zu objects; validation on %zu scene(s)\n", drawer.scenes().size(),
                 drawer.object_count(), val_drawer ? val_drawer->scenes().size() : size_t(0));

    vk::ContextOptions co;
    co.device = a.device.device;
    vk::Context ctx(co);
    auto pool = nn::Pool::create(ctx);
    nn::train::TrainOptions to;
    to.drop_path = a.drop_path;
    to.lovasz_weight = a.lovasz;
    to.seed = a.seed;
    to.adamw.weight_decay = a.weight_decay;
    auto weights = ckpt ? nn::Ptv3Weights::from_host(*pool, config, ckpt->weights, a.resume)
                        : nn::Ptv3Weights::from_host(*pool, config, nn::train::initial_weights(config, a.seed), "initial");
    nn::train::Trainer trainer(*pool, std::move(weights), to);
    int64_t start = 0;
    if (ckpt) {
        nn::train::restore_optimizer(trainer, *ckpt);
        start = ckpt->step;
        ckpt.reset();
    }
    nn::train::OneCycle schedule;
    schedule.max_lr = a.lr;
    schedule.total_steps = a.steps;

    std::vector<data::train::Sample> val_samples;
    if (val_drawer) {
        data::Rng rng(step_seed(a.seed, -1, 7));
        for (int i = 0; i < a.val_samples; ++i) val_samples.push_back(val_drawer->draw(rng));
    }
    const std::string stem = a.out.substr(0, a.out.size() - std::string(".safetensors").size());
    const std::string ckpt_path = stem + ".ckpt.safetensors", log_path = stem + ".log.jsonl",
                      curves_path = stem + ".curves.png";
    std::ofstream log(log_path, start > 0 ? std::ios::app : std::ios::trunc);
    const bool tty = isatty(2) && !std::getenv("CI");
    const auto t_start = std::chrono::steady_clock::now();
    double loss_avg = 0, acc_avg = 0, extra_clicks = 0;
    int64_t averaged = 0;
    Validation last_val;
    auto metadata = [&](int64_t step) {
        nlohmann::json info = {{"steps", step},           {"batch", a.batch},   {"points", a.points},
                               {"max_lr", a.lr},          {"seed", a.seed},     {"device", ctx.info().name},
                               {"train_scenes", drawer.scenes().size()},        {"drop_path", a.drop_path},
                               {"lovasz", a.lovasz},
                               {"val_iou1", last_val.iou1}, {"val_iou3", last_val.iou3}};
        return std::map<std::string, std::string>{{"training", info.dump()}};
    };

    const int64_t end = a.stop_at > 0 ? std::min<int64_t>(a.stop_at, a.steps) : a.steps;
    for (int64_t step = start; step < end; ++step) {
        const auto t0 = std::chrono::steady_clock::now();
        data::Rng rng(step_seed(a.seed, step, 1));
        trainer.rng().seed(step_seed(a.seed, step, 2));
        // Samples; some get later clicks on the current model's own errors (the benchmark's protocol).
        std::vector<data::train::Sample> samples;
        std::unique_ptr<nn::Ptv3> model;
        for (int b = 0; b < a.batch; ++b) {
            data::train::Sample s = drawer.draw(rng);
            const int clicks = rng.below(a.max_clicks + 1);
            for (int k = 0; k < clicks; ++k) {
                if (!model) model = std::make_unique<nn::Ptv3>(*pool, trainer.weights());
                if (!drawer.add_click(s, predict(*model, s))) break;
                extra_clicks += 1;
            }
            samples.push_back(std::move(s));
        }
        model.reset();
        std::vector<int32_t> labels;
        const nn::Ptv3Input in = batch_input(samples, labels);
        const auto r = trainer.step(in, labels, schedule.lr(step), schedule.beta1(step));
        if (!std::isfinite(r.loss)) throw std::runtime_error("training diverged at step " + std::to_string(step) + " (loss is not finite)");
        size_t right = 0;
        for (size_t i = 0; i < labels.size(); ++i) right += (r.logits[2 * i + 1] > r.logits[2 * i]) == (labels[i] == 1);
        const double acc = double(right) / double(labels.size());
        const double k = averaged < 20 ? 1.0 / double(++averaged) : 0.05;
        loss_avg += k * (r.loss - loss_avg);
        acc_avg += k * (acc - acc_avg);
        const double step_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
        const double rate = double(step + 1 - start) / elapsed;
        nlohmann::json entry = {{"step", step + 1}, {"loss", r.loss}, {"accuracy", acc}, {"lr", schedule.lr(step)},
                                {"seconds", step_s}, {"points", labels.size()}};
        if (a.lovasz > 0) entry["lovasz"] = r.lovasz;

        const bool last = step + 1 == a.steps;
        if (val_drawer && ((step + 1) % a.val_every == 0 || last)) {
            last_val = validate(*pool, trainer.weights(), *val_drawer, val_samples);
            entry["val_iou1"] = last_val.iou1;
            entry["val_iou3"] = last_val.iou3;
            std::fprintf(stderr, "%sstep %lld: loss %.4f, accuracy %.3f, validation IoU %.3f (1 click) %.3f (3 clicks)\n",
                         tty ? "\r\x1b[K" : "", (long long)(step + 1), loss_avg, acc_avg, last_val.iou1, last_val.iou3);
        }
        log << entry.dump() << "\n" << std::flush;
        if (tty)
            std::fprintf(stderr, "\rstep %lld/%d  loss %.4f  acc %.3f  %.2f steps/s  eta %.0f min\x1b[K", (long long)(step + 1),
                         a.steps, loss_avg, acc_avg, rate, double(a.steps - step - 1) / rate / 60.0);
        else if ((step + 1) % 50 == 0)
            std::fprintf(stderr, "step %lld/%d loss %.4f acc %.3f %.2f steps/s\n", (long long)(step + 1), a.steps, loss_avg,
                         acc_avg, rate);
        if ((step + 1) % a.checkpoint_every == 0 && !last)
            nn::train::save_checkpoint(ckpt_path, trainer, step + 1, metadata(step + 1));
    }
    if (tty) std::fprintf(stderr, "\n");
    if (end < a.steps) {
        nn::train::save_checkpoint(ckpt_path, trainer, end, metadata(end));
        log.close();
        write_train_curves(log_path, curves_path);
        std::printf("stopped after step %lld of %d: resume with --resume %s\n", (long long)end, a.steps, ckpt_path.c_str());
        return;
    }

    // The running statistics trail the weights; settle them on fresh training samples.
    std::vector<nn::Ptv3Input> calib;
    data::Rng rng(step_seed(a.seed, a.steps, 3));
    for (int i = 0; i < a.calibration; ++i) calib.push_back(sample_input(drawer.draw(rng)));
    trainer.calibrate_batch_norm(calib);
    if (val_drawer) last_val = validate(*pool, trainer.weights(), *val_drawer, val_samples);
    nn::train::save_checkpoint(ckpt_path, trainer, a.steps, metadata(a.steps));
    nn::train::save_model(a.out, *pool, trainer.weights(), metadata(a.steps));
    log.close();
    write_train_curves(log_path, curves_path);
    const double minutes = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count() / 60.0;
    std::printf("wrote %s (%lld parameters) after %d steps in %.1f min on %s", a.out.c_str(),
                trainer.weights().parameter_count(), a.steps, minutes, ctx.info().name.c_str());
    if (val_drawer) std::printf("; validation IoU %.3f (1 click), %.3f (3 clicks)", last_val.iou1, last_val.iou3);
    std::printf("\n");
}

}  // namespace

void register_train(CLI::App& app, std::function<void()>& run) {
    auto a = std::make_shared<TrainArgs>();
    auto* cmd = app.add_subcommand("train", "Train the interactive PTv3 on labelled scenes");
    cmd->add_option("--data", a->data, "Training scenes: suite folders (their train split), scene folders or PLYs with 'instance'")
        ->required();
    cmd->add_option("--val", a->val, "Validation scenes: suite folders (their test split), scene folders or PLYs");
    cmd->add_option("--config", a->config, "tiny, small, paper, or a model file whose config to use")->capture_default_str();
    cmd->add_option("--out", a->out, "Model file to write (.safetensors); OUT.ckpt.safetensors and OUT.log.jsonl beside it")
        ->required();
    cmd->add_option("--steps", a->steps, "Optimizer steps in all (the schedule's length)")->capture_default_str();
    cmd->add_option("--batch", a->batch, "Samples (clouds) per step")->capture_default_str();
    cmd->add_option("--points", a->points, "N_max: points per sample")->capture_default_str();
    cmd->add_option("--clicks", a->max_clicks, "Most later clicks simulated on the model's errors per sample")
        ->capture_default_str();
    cmd->add_option("--lr", a->lr, "Peak learning rate (OneCycle)")->capture_default_str();
    cmd->add_option("--weight-decay", a->weight_decay, "AdamW weight decay")->capture_default_str();
    cmd->add_option("--drop-path", a->drop_path, "Drop path rate of the deepest block")->capture_default_str();
    cmd->add_option("--lovasz", a->lovasz, "Weight of a Lovasz-softmax loss added to the cross-entropy (0: off)")
        ->capture_default_str();
    cmd->add_option("--seed", a->seed, "Seed of weights, samples and drop path")->capture_default_str();
    cmd->add_option("--val-every", a->val_every, "Validate every N steps")->capture_default_str();
    cmd->add_option("--val-samples", a->val_samples, "Fixed validation samples")->capture_default_str();
    cmd->add_option("--checkpoint-every", a->checkpoint_every, "Write the checkpoint every N steps")->capture_default_str();
    cmd->add_option("--calibration", a->calibration, "Samples that settle the BatchNorm statistics at the end")
        ->capture_default_str();
    cmd->add_option("--resume", a->resume, "Continue from this checkpoint (OUT.ckpt.safetensors)");
    cmd->add_option("--stop-at", a->stop_at, "Stop after this step, writing the checkpoint only (train in chunks)");
    add_device_option(*cmd, a->device);
    cmd->callback([a, &run] { run = [a] { run_train(*a); }; });
}

}  // namespace pg::app

#include "nn/train/training_run.h"

#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <memory>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "dataset/random.h"
#include "dataset/report/train_curves.h"
#include "engine/vk/context.h"
#include "nn/train/batch.h"
#include "nn/train/checkpoint.h"

namespace pg::nn::train {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// Streams: 1 samples, 2 drop path, 3 calibration, 7 validation samples (step -1).
uint64_t step_seed(uint64_t seed, int64_t step, uint64_t stream) {
    return seed * 0x9E3779B97F4A7C15ull + uint64_t(step) * 0xD1B54A32D192ED03ull + stream;
}

// A step's samples; each gets up to max_clicks later clicks on the current weights' errors.
Batch draw_batch(Trainer& trainer, const data::train::SampleDrawer& drawer, data::Rng& rng, const RunOptions& o) {
    Batch batch;
    std::unique_ptr<Ptv3> model;  // made only when a sample needs it
    for (int b = 0; b < o.batch; ++b) {
        data::train::Sample s = drawer.draw(rng);
        const int clicks = rng.below(o.max_clicks + 1);
        for (int k = 0; k < clicks; ++k) {
            if (!model) model = std::make_unique<Ptv3>(trainer.pool(), trainer.weights());
            if (!drawer.add_click(s, predict_mask(*model, s))) break;
        }
        batch.add(s);
    }
    return batch;
}

double accuracy(const std::vector<float>& logits, const std::vector<int32_t>& labels) {
    size_t right = 0;
    for (size_t i = 0; i < labels.size(); ++i) right += (logits[2 * i + 1] > logits[2 * i]) == (labels[i] == 1);
    return double(right) / double(labels.size());
}

// Fixed for the whole run (and its resumptions).
std::vector<data::train::Sample> validation_samples(const data::train::SampleDrawer* drawer, const RunOptions& o) {
    std::vector<data::train::Sample> samples;
    if (!drawer) return samples;
    data::Rng rng(step_seed(o.seed, -1, 7));
    for (int i = 0; i < o.val_samples; ++i) samples.push_back(drawer->draw(rng));
    return samples;
}

// The running statistics trail the weights; settle them on fresh training samples.
void calibrate(Trainer& trainer, const data::train::SampleDrawer& drawer, const RunOptions& o) {
    std::vector<Ptv3Input> inputs;
    data::Rng rng(step_seed(o.seed, o.steps, 3));
    for (int i = 0; i < o.calibration; ++i) inputs.push_back(sample_input(drawer.draw(rng)));
    trainer.calibrate_batch_norm(inputs);
}

// The metadata["training"] of checkpoints and the model file.
std::map<std::string, std::string> run_metadata(Trainer& trainer, const data::train::SampleDrawer& drawer,
                                                const RunOptions& o, int64_t step,
                                                const std::optional<Validation>& validation) {
    const Validation v = validation.value_or(Validation{});
    const nlohmann::json info = {{"steps", step},
                                 {"batch", o.batch},
                                 {"points", drawer.options().max_points},
                                 {"max_lr", o.lr},
                                 {"seed", o.seed},
                                 {"device", trainer.pool().context().info().name},
                                 {"train_scenes", drawer.scenes().size()},
                                 {"drop_path", trainer.options().drop_path},
                                 {"lovasz", trainer.options().lovasz_weight},
                                 {"val_iou1", v.iou1},
                                 {"val_iou3", v.iou3}};
    return {{"training", info.dump()}};
}

}  // namespace

RunResult run_training(Trainer& trainer, int64_t start, const data::train::SampleDrawer& drawer,
                       const data::train::SampleDrawer* val_drawer, const RunOptions& o,
                       const std::function<void(const StepReport&)>& report) {
    OneCycle schedule;
    schedule.max_lr = o.lr;
    schedule.total_steps = o.steps;
    const std::vector<data::train::Sample> val_samples = validation_samples(val_drawer, o);
    const std::string out = o.out.string();
    const std::string stem = out.substr(0, out.size() - std::string(".safetensors").size());
    RunResult result;
    result.checkpoint = stem + ".ckpt.safetensors";
    const std::string log_path = stem + ".log.jsonl", curves_path = stem + ".curves.png";
    std::ofstream log(log_path, start > 0 ? std::ios::app : std::ios::trunc);
    const auto t_start = Clock::now();
    StepReport progress;
    int64_t averaged = 0;
    auto metadata = [&](int64_t step) { return run_metadata(trainer, drawer, o, step, result.validation); };
    auto finish_log = [&] {
        log.close();
        data::report::write_train_curves(log_path, curves_path);
        result.seconds = seconds_since(t_start);
        return result;
    };

    const int64_t end = o.stop_at > 0 ? std::min<int64_t>(o.stop_at, o.steps) : o.steps;
    for (int64_t step = start; step < end; ++step) {
        const auto t0 = Clock::now();
        data::Rng rng(step_seed(o.seed, step, 1));
        trainer.rng().seed(step_seed(o.seed, step, 2));
        const Batch batch = draw_batch(trainer, drawer, rng, o);
        const auto r = trainer.step(batch.input, batch.labels, schedule.lr(step), schedule.beta1(step));
        if (!std::isfinite(r.loss))
            throw std::runtime_error("training diverged at step " + std::to_string(step) + " (loss is not finite)");
        const double acc = accuracy(r.logits, batch.labels);
        const double k = averaged < 20 ? 1.0 / double(++averaged) : 0.05;
        progress.step = step + 1;
        progress.loss += k * (r.loss - progress.loss);
        progress.accuracy += k * (acc - progress.accuracy);
        nlohmann::json entry = {{"step", step + 1}, {"loss", r.loss}, {"accuracy", acc}, {"lr", schedule.lr(step)},
                                {"seconds", seconds_since(t0)}, {"points", batch.labels.size()}};
        progress.steps_per_s = double(step + 1 - start) / seconds_since(t_start);
        if (trainer.options().lovasz_weight > 0) entry["lovasz"] = r.lovasz;

        const bool last = step + 1 == o.steps;
        progress.validation = nullptr;
        if (val_drawer && ((step + 1) % o.val_every == 0 || last)) {
            result.validation = validate(trainer.pool(), trainer.weights(), *val_drawer, val_samples);
            entry["val_iou1"] = result.validation->iou1;
            entry["val_iou3"] = result.validation->iou3;
            progress.validation = &*result.validation;
        }
        log << entry.dump() << "\n" << std::flush;
        report(progress);
        if ((step + 1) % o.checkpoint_every == 0 && !last)
            save_checkpoint(result.checkpoint, trainer, step + 1, metadata(step + 1));
    }
    result.steps = end;
    if (end < o.steps) {
        save_checkpoint(result.checkpoint, trainer, end, metadata(end));
        return finish_log();
    }

    calibrate(trainer, drawer, o);
    if (val_drawer) result.validation = validate(trainer.pool(), trainer.weights(), *val_drawer, val_samples);
    save_checkpoint(result.checkpoint, trainer, o.steps, metadata(o.steps));
    save_model(o.out, trainer.pool(), trainer.weights(), metadata(o.steps));
    result.finished = true;
    return finish_log();
}

}  // namespace pg::nn::train

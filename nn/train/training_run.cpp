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

// The running statistics trail the weights; settle them on fresh training samples.
void calibrate(Trainer& trainer, const TrainingTask& task, const RunOptions& o) {
    std::vector<Ptv3Input> inputs;
    data::Rng rng(step_seed(o.seed, o.steps, 3));
    for (int i = 0; i < o.calibration; ++i) inputs.push_back(task.calibration_input(rng));
    trainer.calibrate_batch_norm(inputs);
}

// The metadata["training"] of checkpoints and the model file.
std::map<std::string, std::string> run_metadata(Trainer& trainer, const TrainingTask& task, const RunOptions& o,
                                                int64_t step, const std::optional<Validation>& validation) {
    nlohmann::json info = task.describe();
    info.update({{"steps", step},
                 {"batch", o.batch},
                 {"max_lr", o.lr},
                 {"seed", o.seed},
                 {"device", trainer.pool().context().info().name},
                 {"drop_path", trainer.options().drop_path},
                 {"lovasz", trainer.options().lovasz_weight}});
    if (validation)
        for (const auto& [name, value] : validation->scores) info["val_" + name] = value;
    return {{"training", info.dump()}};
}

}  // namespace

RunResult run_training(Trainer& trainer, int64_t start, TrainingTask& task, const RunOptions& o,
                       const std::function<void(const StepReport&)>& report) {
    OneCycle schedule;
    schedule.max_lr = o.lr;
    schedule.total_steps = o.steps;
    data::Rng val_rng(step_seed(o.seed, -1, 7));  // fixed for the whole run (and its resumptions)
    const bool validating = task.prepare_validation(val_rng, o.val_samples);
    const std::string out = o.out.string();
    const std::string stem = out.substr(0, out.size() - std::string(".safetensors").size());
    RunResult result;
    result.checkpoint = stem + ".ckpt.safetensors";
    const std::string log_path = stem + ".log.jsonl", curves_path = stem + ".curves.png";
    std::ofstream log(log_path, start > 0 ? std::ios::app : std::ios::trunc);
    const auto t_start = Clock::now();
    StepReport progress;
    int64_t averaged = 0;
    auto metadata = [&](int64_t step) { return run_metadata(trainer, task, o, step, result.validation); };
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
        const Batch batch = task.draw_batch(&trainer, rng, o.batch, o.max_clicks);
        const auto r = trainer.step(batch.input, batch.labels, schedule.lr(step), schedule.beta1(step));
        if (!std::isfinite(r.loss))
            throw std::runtime_error("training diverged at step " + std::to_string(step) + " (loss is not finite)");
        const double acc = accuracy(r.logits, batch.labels, trainer.config().num_classes);
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
        if (validating && ((step + 1) % o.val_every == 0 || last)) {
            result.validation = task.validate(trainer.pool(), trainer.weights());
            for (const auto& [name, value] : result.validation->scores) entry["val_" + name] = value;
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

    calibrate(trainer, task, o);
    if (validating) result.validation = task.validate(trainer.pool(), trainer.weights());
    save_checkpoint(result.checkpoint, trainer, o.steps, metadata(o.steps));
    save_model(o.out, trainer.pool(), trainer.weights(), metadata(o.steps));
    result.finished = true;
    return finish_log();
}

}  // namespace pg::nn::train

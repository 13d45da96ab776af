#pragma once
// A training run of PTv3, as `pointgauss train` runs it: batches of the task's samples (the
// interactive task's with later clicks on the current model's own errors), AdamW
// steps on the OneCycle schedule, validation on held-out samples, checkpoints, a JSON-lines log
// and its curves; at the end the BatchNorm statistics are settled and the model file written.
// Seeded: every step's samples and drop path masks derive from (seed, step), so a run resumed
// from its checkpoint draws what the uninterrupted one would have.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>

#include "nn/train/trainer.h"
#include "nn/train/training_task.h"
#include "nn/train/validation.h"

namespace pg::nn::train {

struct RunOptions {
    // The model file M.safetensors; M.ckpt.safetensors, M.log.jsonl and M.curves.png go beside it.
    std::filesystem::path out;
    int steps = 2000;  // the schedule's length
    int batch = 2;     // samples per step
    int max_clicks = 3;  // most later clicks per sample
    int val_every = 100, val_samples = 24, checkpoint_every = 100;
    int calibration = 32;  // samples that settle the BatchNorm statistics at the end
    int stop_at = 0;       // stop after this step with the checkpoint only (train in chunks); 0 = run to the end
    double lr = 0.002;     // OneCycle peak
    uint64_t seed = 1;
};

// What a step reports as it ends.
struct StepReport {
    int64_t step = 0;                        // steps done
    double loss = 0, accuracy = 0;           // running means over about the last 20 steps
    double steps_per_s = 0;                  // since the run (or its resumption) started
    const Validation* validation = nullptr;  // when this step validated
};

struct RunResult {
    int64_t steps = 0;      // steps done in all
    bool finished = false;  // the model file is written; else only the checkpoint, to resume from
    std::filesystem::path checkpoint;
    std::optional<Validation> validation;  // the last one, when there are validation samples
    double seconds = 0;
};

// Runs steps `start` (a resumed checkpoint's step) to the end or options.stop_at, validating
// when the task has validation samples. Throws std::runtime_error when the loss stops being finite.
RunResult run_training(Trainer& trainer, int64_t start, TrainingTask& task, const RunOptions& options,
                       const std::function<void(const StepReport&)>& report);

}  // namespace pg::nn::train

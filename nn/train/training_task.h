#pragma once
// What a training run trains on. The interactive task draws a click, its ROI and click
// weights (dataset/train/sample_drawer.h) and later clicks on the current model's errors; the
// semantic task draws a tile column with appearance features and classes
// (dataset/train/semantic_drawer.h). The run itself (schedule, checkpoints, log) is the same.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "dataset/random.h"
#include "dataset/train/sample_drawer.h"
#include "dataset/train/semantic_drawer.h"
#include "nn/train/batch.h"
#include "nn/train/trainer.h"
#include "nn/train/validation.h"

namespace pg::nn::train {

class TrainingTask {
public:
    virtual ~TrainingTask() = default;
    // One step's samples (`batch` clouds). The interactive task gives each up to `max_clicks`
    // later clicks on the trainer's current weights (it needs `trainer`; the semantic task
    // ignores it, and it may be null there).
    virtual Batch draw_batch(Trainer* trainer, data::Rng& rng, int batch, int max_clicks) const = 0;
    // A fresh training sample as one cloud (settles the BatchNorm statistics).
    virtual Ptv3Input calibration_input(data::Rng& rng) const = 0;
    // Draws the fixed validation samples; false when the task has no validation scenes.
    virtual bool prepare_validation(data::Rng& rng, int count) = 0;
    virtual Validation validate(Pool& pool, const Ptv3Weights& weights) const = 0;
    // The model file's metadata["training"] entries that describe the data.
    virtual nlohmann::json describe() const = 0;
};

// Fraction of points whose argmax class is their label (labels outside the classes skipped).
double accuracy(const std::vector<float>& logits, const std::vector<int32_t>& labels, int classes);

class InteractiveTask : public TrainingTask {
public:
    InteractiveTask(const data::train::SampleDrawer& drawer, const data::train::SampleDrawer* validation)
        : drawer_(drawer), val_drawer_(validation) {}
    Batch draw_batch(Trainer* trainer, data::Rng& rng, int batch, int max_clicks) const override;
    Ptv3Input calibration_input(data::Rng& rng) const override;
    bool prepare_validation(data::Rng& rng, int count) override;
    Validation validate(Pool& pool, const Ptv3Weights& weights) const override;
    nlohmann::json describe() const override;

private:
    const data::train::SampleDrawer& drawer_;
    const data::train::SampleDrawer* val_drawer_;
    std::vector<data::train::Sample> val_samples_;
};

// The interactive model's object mask for a sample (1 = object), inference mode.
std::vector<uint8_t> predict_mask(Ptv3& model, const data::train::Sample& sample);

class SemanticTask : public TrainingTask {
public:
    SemanticTask(const data::train::SemanticDrawer& drawer, const data::train::SemanticDrawer* validation)
        : drawer_(drawer), val_drawer_(validation) {}
    Batch draw_batch(Trainer* trainer, data::Rng& rng, int batch, int max_clicks) const override;
    Ptv3Input calibration_input(data::Rng& rng) const override;
    bool prepare_validation(data::Rng& rng, int count) override;
    // Pooled over the samples' points: mean IoU over the classes present, overall accuracy.
    Validation validate(Pool& pool, const Ptv3Weights& weights) const override;
    nlohmann::json describe() const override;

private:
    const data::train::SemanticDrawer& drawer_;
    const data::train::SemanticDrawer* val_drawer_;
    std::vector<data::train::SemanticSample> val_samples_;
};

}  // namespace pg::nn::train

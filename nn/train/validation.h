#pragma once
// Validation of the interactive model during training: IoU on held-out samples after one and
// three clicks.
#include <cstdint>
#include <vector>

#include "dataset/train/sample_drawer.h"
#include "nn/ptv3/model.h"

namespace pg::nn::train {

// The interactive model's object mask for a sample (1 = object), inference mode.
std::vector<uint8_t> predict_mask(Ptv3& model, const data::train::Sample& sample);

struct Validation {
    double iou1 = 0, iou3 = 0;  // mean IoU after the first click and after two more
};

// Mean IoU over fixed held-out samples, inference mode (running statistics), as the pipeline
// runs it; the later clicks follow the benchmark's protocol on the model's own errors.
Validation validate(Pool& pool, const Ptv3Weights& weights, const data::train::SampleDrawer& drawer,
                    std::vector<data::train::Sample> samples);

}  // namespace pg::nn::train

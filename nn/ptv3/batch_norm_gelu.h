#pragma once
// BatchNorm1d then GELU, the tail of the embedding, the pooling and both unpooling projections
// (Pointcept's PointSequential of the two). Inference normalises with the running statistics;
// training with the batch's, updating the running ones.
#include <string>

#include "nn/tensor.h"

namespace pg::nn {

class InferencePass;
class TrainingPass;

class BatchNormGelu {
public:
    explicit BatchNormGelu(std::string name) : name_(std::move(name)) {}

    struct Tape {
        Tensor x, mean, var, y;  // input, batch statistics, normalised (before GELU)
    };
    Tensor forward(InferencePass& pass, const Tensor& x) const;
    Tensor forward(TrainingPass& pass, Tape& tape, const Tensor& x) const;
    Tensor backward(TrainingPass& pass, const Tape& tape, const Tensor& dy) const;

private:
    std::string name_;  // weight prefix
};

}  // namespace pg::nn

#pragma once
// PTv3's pooling into the next coarser level (Pointcept's SerializedPooling): a Linear, the max
// over each cluster of finer voxels, BatchNorm and GELU. The finer features stay on the point
// as the parent the unpooling comes back to.
#include <string>

#include "nn/ptv3/batch_norm_gelu.h"
#include "nn/ptv3/point.h"

namespace pg::nn {

class Pooling {
public:
    explicit Pooling(std::string name) : name_(std::move(name)), norm_(name_ + ".norm.0") {}

    struct Tape {
        Tensor x, lin;  // the finer features (the Linear's input) and the Linear's output
        BatchNormGelu::Tape norm;
    };
    void forward(InferencePass& pass, Ptv3Point& point) const;
    void forward(TrainingPass& pass, Ptv3Point& point) const;
    // Adds the parent's gradient (from the unpooling) to the finer features'.
    void backward(TrainingPass& pass, Ptv3Point& grad) const;

private:
    std::string name_;
    BatchNormGelu norm_;
};

}  // namespace pg::nn

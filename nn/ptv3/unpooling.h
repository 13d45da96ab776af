#pragma once
// PTv3's unpooling back to the finer level (Pointcept's SerializedUnpooling): the coarse features
// and the parent's (the finer level's before its pooling) each through Linear, BatchNorm and
// GELU, then every finer voxel gets its skip projection plus its cluster's coarse projection.
#include <string>

#include "nn/ptv3/batch_norm_gelu.h"
#include "nn/ptv3/point.h"

namespace pg::nn {

class Unpooling {
public:
    explicit Unpooling(std::string name);

    struct Tape {
        Tensor deeper, lin_up, skip_in, lin_skip;
        BatchNormGelu::Tape norm_up, norm_skip;
    };
    // Leaves the skip projection as point.conv_feat (see Ptv3Point).
    void forward(InferencePass& pass, Ptv3Point& point) const;
    void forward(TrainingPass& pass, Ptv3Point& point) const;
    // Takes grad.conv_feat into the skip's gradient; the parent's gradient goes onto grad.parents.
    void backward(TrainingPass& pass, Ptv3Point& grad) const;

private:
    std::string name_;
    BatchNormGelu norm_up_, norm_skip_;
};

}  // namespace pg::nn

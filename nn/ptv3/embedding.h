#pragma once
// PTv3's embedding (Pointcept's Embedding): each voxel's input features (its lowest-index
// point's), a 5x5x5 sparse convolution without bias, BatchNorm and GELU.
#include "nn/ptv3/batch_norm_gelu.h"
#include "nn/ptv3/config.h"
#include "nn/ptv3/point.h"
#include "nn/ptv3/weights.h"

namespace pg::nn {

class Embedding {
public:
    explicit Embedding(const Ptv3Config& config);

    struct Tape {
        Tensor x;  // the voxels' input features (the convolution's input)
        BatchNormGelu::Tape norm;
    };
    // point.feat: per input point in, per level-0 voxel out.
    void forward(InferencePass& pass, Ptv3Point& point) const;
    void forward(TrainingPass& pass, Ptv3Point& point) const;
    // Writes the parameters' gradients; the input features get none.
    void backward(TrainingPass& pass, Ptv3Point& grad) const;

private:
    Tensor conv_weight(const Ptv3Weights& weights) const;

    int64_t in_channels_, channels_;
    BatchNormGelu norm_{"embedding.stem.norm"};
};

}  // namespace pg::nn

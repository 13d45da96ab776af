#pragma once
// PTv3's segmentation head: one Linear from the finest decoder features to the class logits.
#include "nn/ptv3/point.h"

namespace pg::nn {

class InferencePass;
class TrainingPass;

class Head {
public:
    struct Tape {
        Tensor x;  // the decoder's output
    };
    // point.feat becomes the logits per level-0 voxel.
    void forward(InferencePass& pass, Ptv3Point& point) const;
    void forward(TrainingPass& pass, Ptv3Point& point) const;
    void backward(TrainingPass& pass, Ptv3Point& grad) const;
};

}  // namespace pg::nn

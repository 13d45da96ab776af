#include "nn/ptv3/head.h"

#include "nn/ptv3/inference_pass.h"
#include "nn/ptv3/training_pass.h"

namespace pg::nn {

void Head::forward(InferencePass& pass, Ptv3Point& point) const {
    point.feat = pass.linear(point.feat, "head");
    pass.emit("logits/voxels", point.feat);
}

void Head::forward(TrainingPass& pass, Ptv3Point& point) const {
    pass.tape.head.x = point.feat;
    point.feat = pass.linear(point.feat, "head");
}

void Head::backward(TrainingPass& pass, Ptv3Point& grad) const {
    grad.feat = pass.linear_backward(pass.tape.head.x, "head", grad.feat);
}

}  // namespace pg::nn

#include "nn/ptv3/pooling.h"

#include "nn/ops/elementwise.h"
#include "nn/ops/pooling.h"
#include "nn/ptv3/inference_pass.h"
#include "nn/ptv3/training_pass.h"
#include "nn/train/grad_ops.h"

namespace pg::nn {

void Pooling::forward(InferencePass& pass, Ptv3Point& point) const {
    point.parents.push_back(point.feat);
    Tensor x = pass.linear(point.feat, name_ + ".proj");
    ++point.level;
    pass.cmd.begin_pass("pool");
    x = ops::segment_max(pass.cmd, pass.pool, x, point.at().clusters);
    point.feat = norm_.forward(pass, x);
    pass.emit(name_ + "/feat", point.feat);
}

void Pooling::forward(TrainingPass& pass, Ptv3Point& point) const {
    Tape& t = pass.tape.poolings.emplace_back();
    point.parents.push_back(point.feat);
    t.x = point.feat;
    t.lin = pass.linear(t.x, name_ + ".proj");
    ++point.level;
    pass.cmd.begin_pass("pool");
    point.feat = norm_.forward(pass, t.norm, ops::segment_max(pass.cmd, pass.pool, t.lin, point.at().clusters));
}

void Pooling::backward(TrainingPass& pass, Ptv3Point& grad) const {
    const Tape t = take_last(pass.tape.poolings);
    Tensor d = norm_.backward(pass, t.norm, grad.feat);
    pass.cmd.begin_pass("pool bwd");
    d = grad::segment_max_backward(pass.cmd, pass.pool, t.lin, grad.at().clusters, d);
    --grad.level;
    d = pass.linear_backward(t.x, name_ + ".proj", d);
    const Tensor d_parent = take_last(grad.parents);
    grad.feat = d_parent.defined() ? ops::add(pass.cmd, pass.pool, d, d_parent) : d;
}

}  // namespace pg::nn

#include "nn/ptv3/unpooling.h"

#include "nn/ops/elementwise.h"
#include "nn/ptv3/inference_pass.h"
#include "nn/ptv3/training_pass.h"
#include "nn/train/grad_ops.h"

namespace pg::nn {

Unpooling::Unpooling(std::string name)
    : name_(std::move(name)), norm_up_(name_ + ".proj.1"), norm_skip_(name_ + ".proj_skip.1") {}

void Unpooling::forward(InferencePass& pass, Ptv3Point& point) const {
    const Tensor up = norm_up_.forward(pass, pass.linear(point.feat, name_ + ".proj.0"));
    const Tensor skip = norm_skip_.forward(pass, pass.linear(take_last(point.parents), name_ + ".proj_skip.0"));
    pass.cmd.begin_pass("elementwise");
    point.feat = ops::add_gathered(pass.cmd, pass.pool, skip, up, point.at().clusters.cluster);
    point.conv_feat = skip;
    --point.level;
    pass.emit(name_ + "/feat", point.feat);
}

void Unpooling::forward(TrainingPass& pass, Ptv3Point& point) const {
    Tape& t = pass.tape.unpoolings.emplace_back();
    t.deeper = point.feat;
    t.lin_up = pass.linear(t.deeper, name_ + ".proj.0");
    const Tensor up = norm_up_.forward(pass, t.norm_up, t.lin_up);
    t.skip_in = take_last(point.parents);
    t.lin_skip = pass.linear(t.skip_in, name_ + ".proj_skip.0");
    const Tensor skip = norm_skip_.forward(pass, t.norm_skip, t.lin_skip);
    pass.cmd.begin_pass("elementwise");
    point.feat = ops::add_gathered(pass.cmd, pass.pool, skip, up, point.at().clusters.cluster);
    point.conv_feat = skip;
    --point.level;
}

void Unpooling::backward(TrainingPass& pass, Ptv3Point& grad) const {
    const Tape t = take_last(pass.tape.unpoolings);
    // feat = skip + up[cluster]: skip gets d (plus the CPE's, when it convolved the skip), up the cluster sums.
    const Tensor d = grad.feat;
    ++grad.level;
    pass.cmd.begin_pass("elementwise");
    const Tensor d_skip = grad.conv_feat.defined() ? ops::add(pass.cmd, pass.pool, d, grad.conv_feat) : d;
    grad::AddGatheredGrads ag =
        grad::add_gathered_backward(pass.cmd, pass.pool, d, grad::group_rows(grad.at().clusters));
    grad.parents.push_back(
        pass.linear_backward(t.skip_in, name_ + ".proj_skip.0", norm_skip_.backward(pass, t.norm_skip, d_skip)));
    grad.feat = pass.linear_backward(t.deeper, name_ + ".proj.0", norm_up_.backward(pass, t.norm_up, ag.dx));
    grad.conv_feat = {};
}

}  // namespace pg::nn

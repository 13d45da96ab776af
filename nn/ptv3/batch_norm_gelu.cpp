#include "nn/ptv3/batch_norm_gelu.h"

#include <stdexcept>

#include "nn/ops/elementwise.h"
#include "nn/ptv3/inference_pass.h"
#include "nn/ptv3/norm_constants.h"
#include "nn/ptv3/training_pass.h"
#include "nn/train/grad_ops.h"

namespace pg::nn {

Tensor BatchNormGelu::forward(InferencePass& pass, const Tensor& x) const {
    return pass.batch_norm_gelu(x, name_);
}

Tensor BatchNormGelu::forward(TrainingPass& pass, Tape& tape, const Tensor& x) const {
    if (x.dim(0) < 2)
        throw std::invalid_argument("PTv3 training: BatchNorm '" + name_ + "' sees " + std::to_string(x.dim(0)) +
                                    " row(s); a batch needs at least 2 voxels at every level");
    const Ptv3Weights& W = pass.weights;
    pass.cmd.begin_pass("norm");
    grad::BatchNormTrain bn =
        grad::batch_norm_train(pass.cmd, pass.pool, x, W[name_ + ".weight"], W[name_ + ".bias"],
                               W[name_ + ".running_mean"], W[name_ + ".running_var"], kBatchNormEps,
                               float(pass.bn_momentum));
    tape = {x, bn.mean, bn.var, bn.y};
    return ops::gelu(pass.cmd, pass.pool, bn.y);
}

Tensor BatchNormGelu::backward(TrainingPass& pass, const Tape& tape, const Tensor& dy) const {
    pass.cmd.begin_pass("norm bwd");
    Tensor d = grad::gelu_backward(pass.cmd, pass.pool, tape.y, dy);
    grad::NormGrads g = grad::batch_norm_backward(pass.cmd, pass.pool, tape.x, tape.mean, tape.var,
                                                  pass.weights[name_ + ".weight"], d, kBatchNormEps);
    pass.grads[name_ + ".weight"] = g.dgamma;
    pass.grads[name_ + ".bias"] = g.dbeta;
    return g.dx;
}

}  // namespace pg::nn

#include "nn/ptv3/training_pass.h"

#include "nn/ops/elementwise.h"
#include "nn/ops/linear.h"
#include "nn/ops/norm.h"
#include "nn/ptv3/norm_constants.h"
#include "nn/train/drop_path.h"
#include "nn/train/grad_ops.h"

namespace pg::nn {

Tensor TrainingPass::linear(const Tensor& x, const std::string& p, bool bias) {
    cmd.begin_pass("linear");
    return ops::linear(cmd, pool, x, weights[p + ".weight"], bias ? weights[p + ".bias"] : Tensor{});
}

Tensor TrainingPass::linear_backward(const Tensor& x, const std::string& p, const Tensor& dy, bool bias) {
    cmd.begin_pass("linear bwd");
    grad::LinearGrads g = grad::linear_backward(cmd, pool, x, weights[p + ".weight"], dy);
    grads[p + ".weight"] = g.dw;
    if (bias) grads[p + ".bias"] = g.db;
    return g.dx;
}

Tensor TrainingPass::layer_norm(const Tensor& x, const std::string& p, const Tensor& residual) {
    cmd.begin_pass("norm");
    return ops::layer_norm(cmd, pool, x, weights[p + ".weight"], weights[p + ".bias"], kLayerNormEps, residual);
}

Tensor TrainingPass::layer_norm_backward(const Tensor& x, const std::string& p, const Tensor& dy) {
    cmd.begin_pass("norm bwd");
    grad::NormGrads g = grad::layer_norm_backward(cmd, pool, x, weights[p + ".weight"], dy, kLayerNormEps);
    grads[p + ".weight"] = g.dgamma;
    grads[p + ".bias"] = g.dbeta;
    return g.dx;
}

Tensor TrainingPass::keep_mask(int64_t rows, double rate) {
    return rate > 0 ? train::drop_path_mask(cmd, pool, rows, rate, rng_) : Tensor{};
}

Tensor TrainingPass::residual(const Tensor& x, const Tensor& branch, const Tensor& keep) {
    cmd.begin_pass("elementwise");
    return ops::add(cmd, pool, x, keep.defined() ? train::scale_rows(cmd, pool, branch, keep) : branch);
}

Tensor TrainingPass::through_keep(const Tensor& dy, const Tensor& keep) {
    return keep.defined() ? train::scale_rows(cmd, pool, dy, keep) : dy;
}

}  // namespace pg::nn

// Backward of LayerNorm and of BatchNorm in training mode, and the training-mode BatchNorm forward.
#include <algorithm>
#include <stdexcept>
#include <string>

#include "nn/ops/norm.h"
#include "nn/train/grad_ops.h"
#include "nn/train/grad_reduce.h"
#include "shaders/nn/grad_shared.glsl"

namespace pg::nn::grad {

using vk::ceil_div;

NormGrads layer_norm_backward(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Tensor& gamma, const Tensor& dy,
                              float eps) {
    const char* op = "layer_norm_backward";
    detail::expect(op, "x", x, DType::F32, {-1, -1});
    const int64_t M = x.dim(0), C = x.dim(1);
    detail::expect(op, "gamma", gamma, DType::F32, {C});
    detail::expect(op, "dy", dy, DType::F32, {M, C});
    detail::expect_small(op, uint64_t(M) * uint64_t(std::max<int64_t>(C, 3)));
    NormGrads g{pool.empty(x.shape), {}, {}};
    Tensor stats = pool.empty({M, 3});  // row shift, mean and 1/std, for dgamma
    if (M > 0 && C > 0) {
        gpu::RowsPush push{uint32_t(M), uint32_t(C), eps, 0};
        cmd.dispatch("nn/grad_layer_norm", {x, gamma, dy, g.dx, stats}, push, ceil_div(M, 64));
    }
    g.dgamma = detail::column_sums(cmd, pool, PG_COLSUM_ROWNORM, dy, x, stats, uint64_t(M), uint64_t(C));
    g.dbeta = detail::column_sums(cmd, pool, PG_COLSUM_PLAIN, dy, dy, dy, uint64_t(M), uint64_t(C));
    return g;
}

namespace {

int64_t check_batch(const char* op, const Tensor& x) {
    detail::expect(op, "x", x, DType::F32, {-1, -1});
    if (x.dim(0) < 2)
        throw std::invalid_argument(std::string(op) + ": x " + x.shape_string() +
                                    " needs at least 2 rows for batch statistics");
    detail::expect_small(op, uint64_t(x.numel()));
    return x.dim(1);
}

}  // namespace

BatchNormTrain batch_norm_train(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Tensor& gamma,
                                const Tensor& beta, const Tensor& running_mean, const Tensor& running_var, float eps,
                                float momentum) {
    const char* op = "batch_norm_train";
    const int64_t C = check_batch(op, x);
    const uint64_t M = uint64_t(x.dim(0));
    detail::expect(op, "gamma", gamma, DType::F32, {C});
    detail::expect(op, "beta", beta, DType::F32, {C});
    detail::expect(op, "running_mean", running_mean, DType::F32, {C});
    detail::expect(op, "running_var", running_var, DType::F32, {C});
    BatchNormTrain r;
    // Two passes (mean, then squared deviations from it): no cancellation for offset data.
    r.mean = detail::column_sums(cmd, pool, PG_COLSUM_PLAIN, x, x, x, M, uint64_t(C), 1.0f / float(M));
    r.var = detail::column_sums(cmd, pool, PG_COLSUM_SQDEV, x, x, r.mean, M, uint64_t(C), 1.0f / float(M));
    if (C > 0) {
        gpu::RunningStatsPush push{uint32_t(C), uint32_t(M), momentum, 0};
        cmd.dispatch("nn/grad_batch_norm_running", {r.mean, r.var, running_mean, running_var}, push,
                     ceil_div(uint64_t(C), PG_GRAD_THREADS));
    }
    r.y = ops::batch_norm(cmd, pool, x, r.mean, r.var, gamma, beta, eps);
    return r;
}

NormGrads batch_norm_backward(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Tensor& mean, const Tensor& var,
                              const Tensor& gamma, const Tensor& dy, float eps) {
    const char* op = "batch_norm_backward";
    const int64_t C = check_batch(op, x);
    const int64_t M = x.dim(0);
    detail::expect(op, "mean", mean, DType::F32, {C});
    detail::expect(op, "var", var, DType::F32, {C});
    detail::expect(op, "gamma", gamma, DType::F32, {C});
    detail::expect(op, "dy", dy, DType::F32, {M, C});
    NormGrads g;
    g.dbeta = detail::column_sums(cmd, pool, PG_COLSUM_PLAIN, dy, dy, dy, uint64_t(M), uint64_t(C));
    Tensor sum_dev = detail::column_sums(cmd, pool, PG_COLSUM_DEV, dy, x, mean, uint64_t(M), uint64_t(C));
    g.dx = pool.empty(x.shape);
    g.dgamma = pool.empty({C});
    if (C > 0) {
        gpu::RowsPush push{uint32_t(M), uint32_t(C), eps, 0};
        cmd.dispatch("nn/grad_batch_norm", {x, dy, mean, var, gamma, g.dbeta, sum_dev, g.dx, g.dgamma}, push,
                     ceil_div(uint64_t(M) * C, PG_GRAD_THREADS));
    }
    return g;
}

}  // namespace pg::nn::grad

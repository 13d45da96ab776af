#include "nn/ops/norm.h"

#include <initializer_list>
#include <stdexcept>
#include <string>
#include <utility>

#include "shaders/nn/elementwise_shared.glsl"

namespace pg::nn::ops {

namespace {

using vk::ceil_div;

// Rows and channels of x [M, C] (a rank-1 x is one row); checks the per-channel vectors.
void check(const char* op, const Tensor& x, std::initializer_list<std::pair<const char*, const Tensor*>> params,
           uint64_t& rows, uint64_t& channels) {
    if (x.dtype != DType::F32) throw std::invalid_argument(std::string(op) + ": x must be f32");
    if (x.shape.size() != 1 && x.shape.size() != 2)
        throw std::invalid_argument(std::string(op) + ": x " + x.shape_string() + " must be [M, C] or [C]");
    channels = uint64_t(x.dim(-1));
    rows = x.shape.size() == 2 ? uint64_t(x.dim(0)) : 1;
    for (auto& [name, t] : params) {
        if (t->dtype != DType::F32 || t->shape.size() != 1 || uint64_t(t->numel()) != channels)
            throw std::invalid_argument(std::string(op) + ": " + name + " " + t->shape_string() + " must be f32 [" +
                                        std::to_string(channels) + "]");
    }
    if (rows * channels > 0xFFFFFFFFull) throw std::invalid_argument(std::string(op) + ": x too large");
}

}  // namespace

Tensor layer_norm(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Tensor& gamma, const Tensor& beta,
                  float eps, const Tensor& residual) {
    uint64_t rows, c;
    check("layer_norm", x, {{"gamma", &gamma}, {"beta", &beta}}, rows, c);
    if (residual.defined() && (residual.dtype != DType::F32 || residual.shape != x.shape))
        throw std::invalid_argument("layer_norm: residual " + residual.shape_string() + " must be f32 " +
                                    x.shape_string());
    Tensor y = pool.empty(x.shape);
    if (rows == 0 || c == 0) return y;
    const gpu::LayerNormPush push{uint32_t(rows), uint32_t(c), c % 8 == 0, residual.defined(), eps};
    const Tensor& res = residual.defined() ? residual : x;  // bound but unread without a residual
    cmd.dispatch("nn/layer_norm", {x, x, gamma, gamma, beta, beta, res, res, y, y}, push,
                 ceil_div(rows, PG_NORM_THREADS));
    return y;
}

Tensor batch_norm(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Tensor& mean, const Tensor& var,
                  const Tensor& gamma, const Tensor& beta, float eps, bool gelu) {
    uint64_t rows, c;
    check("batch_norm", x, {{"mean", &mean}, {"var", &var}, {"gamma", &gamma}, {"beta", &beta}}, rows, c);
    Tensor y = pool.empty(x.shape);
    if (rows == 0 || c == 0) return y;
    const gpu::BatchNormPush push{uint32_t(rows), uint32_t(c), c % 8 == 0, gelu, eps};
    const uint64_t groups = c % 8 == 0 ? c / 8 : c;
    const uint64_t invocations = groups * ceil_div(rows, PG_BATCH_NORM_ROWS);
    cmd.dispatch("nn/batch_norm", {x, x, mean, mean, var, var, gamma, gamma, beta, beta, y, y}, push,
                 ceil_div(invocations, PG_NORM_THREADS));
    return y;
}

}  // namespace pg::nn::ops

#pragma once
// Normalisation layers at inference: LayerNorm over channels and BatchNorm1d with running
// statistics (optionally followed by GELU, as PTv3's embedding, pooling and unpooling use it).
#include "nn/tensor.h"

namespace pg::nn::ops {

// LayerNorm over the last dim of x [M, C] (biased variance, eps inside the sqrt), gamma/beta [C].
// If `residual` is defined (x's shape), y = residual + LayerNorm(x) (fused residual add).
Tensor layer_norm(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Tensor& gamma, const Tensor& beta,
                  float eps, const Tensor& residual = {});

// Inference BatchNorm1d per channel of x [M, C]: (x - mean) / sqrt(var + eps) * gamma + beta, each [C];
// `gelu` applies exact GELU after.
Tensor batch_norm(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Tensor& mean, const Tensor& var,
                  const Tensor& gamma, const Tensor& beta, float eps, bool gelu = false);

}  // namespace pg::nn::ops

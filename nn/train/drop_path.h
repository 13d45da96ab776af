#pragma once
// Per-point drop path (stochastic depth, as Pointcept's DropPath on a point cloud's features):
// each row of a residual branch is kept with probability 1 - rate and then scaled by
// 1 / (1 - rate), or zeroed. The backward is the same row scaling of the gradient.
#include <cstdint>
#include <random>

#include "nn/tensor.h"

namespace pg::nn::train {

// A keep mask F32 [rows]: 0 or 1 / (1 - rate) per row, drawn from rng on the host and written
// in the stream (cmd.update), so it is safe to record among other work.
Tensor drop_path_mask(vk::CommandList& cmd, Pool& pool, int64_t rows, double rate, std::mt19937_64& rng);

// y[r, :] = x[r, :] * scale[r] for x F32 [rows, C], scale F32 [rows].
Tensor scale_rows(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Tensor& scale);

}  // namespace pg::nn::train

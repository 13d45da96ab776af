#pragma once
// Elementwise f32 ops and row gathers.
#include "nn/tensor.h"

namespace pg::nn::ops {

// Exact GELU 0.5*x*(1+erf(x/sqrt(2))), elementwise on any f32 tensor.
Tensor gelu(vk::CommandList& cmd, Pool& pool, const Tensor& x);

// erf elementwise on any f32 tensor (the approximation GELU uses, shaders/nn/erf.glsl).
Tensor erf(vk::CommandList& cmd, Pool& pool, const Tensor& x);

// a + b elementwise (same shape, f32).
Tensor add(vk::CommandList& cmd, Pool& pool, const Tensor& a, const Tensor& b);

// y[r,:] = x[idx[r],:] for idx [R] int32 (each must be < x.shape[0]); works for any dtype (rows are
// copied as 32-bit words). y has shape [R, x.shape[1..]] and x's dtype.
Tensor gather_rows(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Tensor& idx);

// y[r,:] = a[r,:] + x[idx[r],:] (f32; the unpooling sum). a [R, C], x [P, C], idx [R] int32.
Tensor add_gathered(vk::CommandList& cmd, Pool& pool, const Tensor& a, const Tensor& x, const Tensor& idx);

}  // namespace pg::nn::ops

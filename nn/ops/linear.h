#pragma once
// Matrix products on the GPU: nn.Linear and submanifold sparse convolution (a GEMM whose
// left operand is gathered through a neighbour table). Two kernel families compute them:
// "tiled" (shared-memory tiles, the usual GPU GEMM) and "lanes" (built for CPU Vulkan
// drivers such as lavapipe; see shaders/nn/gemm_lanes.glsl). CPU devices get lanes.
#include "nn/tensor.h"

namespace pg::nn::ops {

enum class Activation { None, Gelu };

// y[M,N] = x[M,K] · w[N,K]^T + bias[N] (PyTorch nn.Linear layout). bias may be an undefined
// Tensor (no bias). If `residual` is defined ([M,N]), y = residual + x·w^T + bias (fused
// residual add). `act` = Gelu gives y = GELU(x·w^T + bias) in the same pass (exact erf GELU;
// not combined with a residual).
Tensor linear(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Tensor& w, const Tensor& bias,
              const Tensor& residual = {}, Activation act = Activation::None);

// y[M,N] = x[M,K] · w[N,K]^T for a deep K and a small output (weight gradients: K is the rows
// of a batch). The same sums as linear() without bias; on the lanes path the depth is split over
// the workgroups of one dispatch in slices of 64 (at most `max_partial_floats` of partial sums)
// and the slices added in order, instead of one dispatch per 64 of depth that one workgroup runs.
Tensor linear_deep(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Tensor& w,
                   uint64_t max_partial_floats = uint64_t(1) << 24);

// Submanifold sparse convolution (nn/ops/sparse_conv.cpp). x [P, Cin] f32; nbr [M, T] int32 (T = kernel
// volume; entry -1 = no neighbour; others must be < P); w [Cout, T*Cin] f32 (spconv's
// [out, kx, ky, kz, in] flattened, so column t*Cin + c multiplies x[nbr[m,t], c]); bias [Cout] or
// undefined. y[m,o] = bias[o] + sum_t sum_c w[o, t*Cin+c] * x[nbr[m,t], c]. Where it runs over a
// rulebook (sparse_conv.h) it builds one each call: over one table several times, build it once.
Tensor sparse_conv(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Tensor& nbr, const Tensor& w,
                   const Tensor& bias);

// Kernel family choice, for tests and benchmarks. Auto: lanes on CPU devices, tiled elsewhere.
enum class GemmPath { Auto, Tiled, Lanes };
void set_gemm_path(GemmPath path);
GemmPath gemm_path();

namespace detail {
bool use_lanes(vk::Context& ctx);  // the kernel family gemm_path() picks on this device
// sparse_conv as one GEMM over all T*Cin columns of A, missing neighbours multiplied as zeros:
// for the shapes the rulebook kernels (nn/ops/sparse_conv.h) do not cover. Shapes checked.
Tensor gathered_conv(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Tensor& nbr, const Tensor& w,
                     const Tensor& bias);
}  // namespace detail

}  // namespace pg::nn::ops

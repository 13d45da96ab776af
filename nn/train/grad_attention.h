#pragma once
// Backward of PTv3's serialized window attention (nn::ops::window_attention) for training.
//
// Flash-attention style: the N x K probabilities are never stored. A per-query pass recomputes
// each window's softmax (logsumexp and out), keeps D_i = dout_i . out_i and writes dq; a per-key
// pass recomputes the probabilities from q, k and the logsumexp and writes dk, dv. Every sum runs
// in a fixed order (no float atomics), so reruns on one device are bit-identical.
#include "nn/ops/attention.h"
#include "nn/tensor.h"

namespace pg::nn::grad {

// Takes the forward's arguments (qkv [N, 3C] f32 point order, order [N] i32 position -> point,
// a permutation, offsets [B+1] i32, heads, patch, scale; head dimension C / heads one of 8, 16,
// 32, 64) and dout [N, C] f32, the loss gradient of the forward's output. Returns dqkv [N, 3C],
// columns [dq | dk | dv] like qkv.
//   dq_i = scale * sum_{j in W(i)} P_ij (dout_i . v_j - D_i) k_j
//   dk_j = scale * sum_{i : j in W(i)} P_ij (dout_i . v_j - D_i) q_i,  dv_j = sum_{i : j in W(i)} P_ij dout_i
// A key belongs to at most two windows (its K-aligned one and the cloud's pulled-back last one);
// the two contributions are added in that order.
Tensor window_attention_backward(vk::CommandList& cmd, Pool& pool, const Tensor& qkv, const Tensor& order,
                                 const Tensor& offsets, int heads, int patch, float scale, const Tensor& dout);
// The same with the kernels chosen: Gpu gives each invocation one position, Cpu (for CPU
// drivers, needs shaderInt64) a block of one window's positions, so each load serves several;
// Auto picks by device type. Tests run both.
Tensor window_attention_backward(vk::CommandList& cmd, Pool& pool, const Tensor& qkv, const Tensor& order,
                                 const Tensor& offsets, int heads, int patch, float scale, const Tensor& dout,
                                 ops::AttentionKernel kernel);

}  // namespace pg::nn::grad

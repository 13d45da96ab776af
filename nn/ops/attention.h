#pragma once
// PTv3's serialized window attention (Pointcept SerializedAttention without relative
// position encoding): a gather of keys/values into serialized order, then one flash-style
// kernel (queries and a running softmax in registers, keys streamed once per query block).
#include "nn/tensor.h"

namespace pg::nn::ops {

// qkv: [N, 3C] f32 in point order, columns [q | k | v], head h on channels [h*D, (h+1)*D) of
// each (D = C / heads, one of 8, 16, 32, 64). order: [N] i32, the point at each serialized
// position. offsets: [B+1] i32 on the device, positions offsets[b] .. offsets[b+1]-1 are
// cloud b (offsets[B] must equal N). Within cloud b (n_b positions), local position l attends
// to the min(patch, n_b) positions from offsets[b] + (n_b <= patch ? 0 :
// min(floor(l / patch) * patch, n_b - patch)): windows of `patch`, the last one pulled back
// to end with the cloud, as the release's padding does. Returns softmax(scale * q k^T) v per
// head, [N, C] f32 in point order (the proj Linear is the caller's). Reads of malformed
// order/offsets are clamped into bounds; the result is then meaningless but memory-safe.
Tensor window_attention(vk::CommandList& cmd, Pool& pool, const Tensor& qkv, const Tensor& order,
                        const Tensor& offsets, int heads, int patch, float scale);

// Two kernels compute the same thing: Gpu stages keys through shared memory for many
// one-query invocations; Cpu (for CPU drivers like lavapipe, needs shaderInt64) gives each
// invocation many queries and no shared memory. Auto picks by device type; tests run both.
enum class AttentionKernel { Auto, Gpu, Cpu };
// Whether `kernel` means the Cpu kernels on this device (Auto: a CPU device), forward and backward.
bool cpu_attention(vk::Context& ctx, AttentionKernel kernel);
Tensor window_attention(vk::CommandList& cmd, Pool& pool, const Tensor& qkv, const Tensor& order,
                        const Tensor& offsets, int heads, int patch, float scale, AttentionKernel kernel);

// The kernels compiled for one head dimension (a compile-time constant of each:
// shaders/nn/*attention*_d*.comp), forward and backward (nn/train/grad_attention) in one list,
// so both accept the same dimensions. Null for a head dimension without kernels.
struct AttentionShaders {
    int64_t head_dim;
    const char* gpu;  // forward, AttentionKernel::Gpu
    const char* cpu;  // forward, AttentionKernel::Cpu
    const char* dq;   // backward: dq and the softmax statistics
    const char* dkv;  // backward: dk, dv
    const char* cpu_dq;   // backward for CPU drivers: the same, many positions per invocation
    const char* cpu_dkv;
};
const AttentionShaders* attention_shaders(int64_t head_dim);

}  // namespace pg::nn::ops

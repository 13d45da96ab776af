#include "nn/train/grad_attention.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "engine/vk/context.h"
#include "nn/ops/attention.h"
#include "nn/train/grad_reduce.h"
#include "shaders/nn/attention_config.glsl"
#include "shaders/nn/grad_attention_config.glsl"

namespace pg::nn::grad {

Tensor window_attention_backward(vk::CommandList& cmd, Pool& pool, const Tensor& qkv, const Tensor& order,
                                 const Tensor& offsets, int heads, int patch, float scale, const Tensor& dout) {
    return window_attention_backward(cmd, pool, qkv, order, offsets, heads, patch, scale, dout,
                                     ops::AttentionKernel::Auto);
}

Tensor window_attention_backward(vk::CommandList& cmd, Pool& pool, const Tensor& qkv, const Tensor& order,
                                 const Tensor& offsets, int heads, int patch, float scale, const Tensor& dout,
                                 ops::AttentionKernel kernel) {
    const char* op = "window_attention_backward";
    auto require = [op](bool ok, const std::string& what) {
        if (!ok) throw std::invalid_argument(std::string(op) + ": " + what);
    };
    require(qkv.dtype == DType::F32 && qkv.shape.size() == 2 && qkv.dim(1) % 3 == 0,
            "qkv must be f32 [N, 3C], got " + std::string(dtype_name(qkv.dtype)) + " " + qkv.shape_string());
    const int64_t n = qkv.dim(0), channels = qkv.dim(1) / 3;
    require(heads > 0 && channels % heads == 0,
            std::to_string(channels) + " channels do not split into " + std::to_string(heads) + " heads");
    const int64_t head_dim = channels / heads;
    const ops::AttentionShaders* kernels = ops::attention_shaders(head_dim);
    require(kernels, "head dimension " + std::to_string(head_dim) + " is not one of 8, 16, 32, 64");
    detail::expect(op, "order", order, DType::I32, {n});
    detail::expect(op, "dout", dout, DType::F32, {n, channels});
    require(offsets.dtype == DType::I32 && offsets.shape.size() == 1 && offsets.dim(0) >= 2,
            "offsets must be i32 [B+1] with B >= 1, got " + std::string(dtype_name(offsets.dtype)) + " " +
                offsets.shape_string());
    require(patch > 0, "patch size " + std::to_string(patch) + " must be positive");
    require(std::isfinite(scale), "scale must be finite");
    // The gathered buffer holds 4C floats per point: its vec4 count must index in 32 bits.
    detail::expect_small(op, uint64_t(n) * uint64_t(channels) * 4u);
    const VkDeviceSize range = pool.context().info().max_storage_buffer_range;
    require(uint64_t(n) * uint64_t(channels) * 16u <= range,
            "the gathered inputs of qkv " + qkv.shape_string() + " exceed the device's storage-buffer range");

    Tensor dqkv = pool.empty({n, 3 * channels}, DType::F32);
    if (n == 0) return dqkv;
    gpu::GradAttentionPush push{};
    push.rows = uint32_t(n);
    push.clouds = uint32_t(offsets.dim(0) - 1);
    push.heads = uint32_t(heads);
    push.channels = uint32_t(channels);
    push.window = uint32_t(patch);
    push.head_dim = uint32_t(head_dim);
    push.scale2 = float(double(scale) * 1.4426950408889634);  // exp2 in the kernels
    push.scale = scale;

    Tensor gathered = pool.empty({heads, n, 4 * head_dim}, DType::F32);
    cmd.dispatch("nn/grad_attention_gather", {qkv, order, dout, gathered}, push,
                 vk::ceil_div(uint64_t(gathered.numel() / 4), PG_GRAD_ATTN_THREADS));
    Tensor stats = pool.empty({heads, n, 2}, DType::F32);
    if (ops::cpu_attention(pool.context(), kernel)) {
        // Workgroups: heads x windows (numbered floor(offsets[b] / K) + b + local, an upper
        // bound) x blocks per window; numbers past a cloud's windows return at once.
        const int64_t block = PG_ATTN_CPU_THREADS * PG_GRAD_ATTN_CPU_ROWS(head_dim);
        push.windows = uint32_t(n / patch + int64_t(push.clouds));
        push.subs = uint32_t((patch + block - 1) / block);
        const uint64_t groups = uint64_t(heads) * push.windows * push.subs;
        cmd.dispatch(kernels->cpu_dq, {gathered, order, offsets, stats, dqkv}, push, groups);
        cmd.dispatch(kernels->cpu_dkv, {gathered, order, offsets, stats, dqkv}, push, groups);
        return dqkv;
    }
    const uint32_t groups = vk::ceil_div(uint64_t(heads) * uint64_t(n), PG_GRAD_ATTN_THREADS);
    cmd.dispatch(kernels->dq, {gathered, order, offsets, stats, dqkv}, push, groups);
    cmd.dispatch(kernels->dkv, {gathered, order, offsets, stats, dqkv}, push, groups);
    return dqkv;
}

}  // namespace pg::nn::grad

#include "nn/ops/attention.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "engine/vk/context.h"
#include "shaders/nn/attention_config.glsl"

namespace pg::nn::ops {

namespace {

void require(bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("window_attention: " + what);
}

constexpr AttentionShaders kAttentionShaders[] = {
    {8, "nn/attention_d8", "nn/attention_cpu_d8", "nn/grad_attention_dq_d8", "nn/grad_attention_dkv_d8",
     "nn/grad_attention_cpu_dq_d8", "nn/grad_attention_cpu_dkv_d8"},
    {16, "nn/attention_d16", "nn/attention_cpu_d16", "nn/grad_attention_dq_d16", "nn/grad_attention_dkv_d16",
     "nn/grad_attention_cpu_dq_d16", "nn/grad_attention_cpu_dkv_d16"},
    {32, "nn/attention_d32", "nn/attention_cpu_d32", "nn/grad_attention_dq_d32", "nn/grad_attention_dkv_d32",
     "nn/grad_attention_cpu_dq_d32", "nn/grad_attention_cpu_dkv_d32"},
    {64, "nn/attention_d64", "nn/attention_cpu_d64", "nn/grad_attention_dq_d64", "nn/grad_attention_dkv_d64",
     "nn/grad_attention_cpu_dq_d64", "nn/grad_attention_cpu_dkv_d64"},
};

}  // namespace

const AttentionShaders* attention_shaders(int64_t head_dim) {
    for (const AttentionShaders& s : kAttentionShaders)
        if (s.head_dim == head_dim) return &s;
    return nullptr;
}

Tensor window_attention(vk::CommandList& cmd, Pool& pool, const Tensor& qkv, const Tensor& order,
                        const Tensor& offsets, int heads, int patch, float scale) {
    return window_attention(cmd, pool, qkv, order, offsets, heads, patch, scale, AttentionKernel::Auto);
}

bool cpu_attention(vk::Context& ctx, AttentionKernel kernel) {
    return kernel == AttentionKernel::Auto ? ctx.info().type == VK_PHYSICAL_DEVICE_TYPE_CPU
                                           : kernel == AttentionKernel::Cpu;
}

Tensor window_attention(vk::CommandList& cmd, Pool& pool, const Tensor& qkv, const Tensor& order,
                        const Tensor& offsets, int heads, int patch, float scale, AttentionKernel kernel) {
    require(qkv.dtype == DType::F32 && qkv.shape.size() == 2 && qkv.dim(1) % 3 == 0,
            "qkv must be f32 [N, 3C], got " + std::string(dtype_name(qkv.dtype)) + " " + qkv.shape_string());
    const int64_t n = qkv.dim(0), channels = qkv.dim(1) / 3;
    require(heads > 0 && channels % heads == 0,
            std::to_string(channels) + " channels do not split into " + std::to_string(heads) + " heads");
    const int64_t head_dim = channels / heads;
    const AttentionShaders* kernels = attention_shaders(head_dim);
    require(kernels, "head dimension " + std::to_string(head_dim) + " is not one of 8, 16, 32, 64");
    require(order.dtype == DType::I32 && order.shape == std::vector<int64_t>{n},
            "order must be i32 [" + std::to_string(n) + "], got " + dtype_name(order.dtype) + " " +
                order.shape_string());
    require(offsets.dtype == DType::I32 && offsets.shape.size() == 1 && offsets.dim(0) >= 2,
            "offsets must be i32 [B+1] with B >= 1, got " + std::string(dtype_name(offsets.dtype)) + " " +
                offsets.shape_string());
    require(patch > 0, "patch size " + std::to_string(patch) + " must be positive");
    require(std::isfinite(scale), "scale must be finite");
    require(n < (int64_t(1) << 31) / 3 / channels, "qkv " + qkv.shape_string() + " is too large to index");
    const VkDeviceSize range = pool.context().info().max_storage_buffer_range;
    require(qkv.bytes() <= range, "qkv " + qkv.shape_string() + " exceeds the device's storage-buffer range");

    Tensor out = pool.empty({n, channels}, DType::F32);
    if (n == 0) return out;
    const int64_t clouds = offsets.dim(0) - 1;
    const int d = int(head_dim);
    // CPU drivers get the variant that gives each invocation many queries (see the config).
    const bool cpu = cpu_attention(pool.context(), kernel);
    const int64_t block = cpu ? PG_ATTN_CPU_THREADS * PG_ATTN_CPU_ROWS(d) : PG_ATTN_GPU_THREADS * PG_ATTN_GPU_ROWS;
    gpu::AttentionPush push{};
    push.rows = uint32_t(n);
    push.clouds = uint32_t(clouds);
    push.heads = uint32_t(heads);
    push.channels = uint32_t(channels);
    push.window = uint32_t(patch);
    // Blocks are numbered floor(offsets[b] / block) + b + local block (see attention_common).
    push.chunks = uint32_t(n / block + clouds);
    push.scale = float(double(scale) * 1.4426950408889634);  // exp2 in the kernels
    push.head_dim = uint32_t(d);

    Tensor kv = pool.empty({heads, n, 2 * head_dim}, DType::F32);
    cmd.dispatch("nn/attention_gather", {qkv, order, kv}, push,
                 vk::ceil_div(uint64_t(kv.numel() / 4), PG_ATTN_GATHER_THREADS));
    cmd.dispatch(cpu ? kernels->cpu : kernels->gpu, {qkv, order, offsets, out, kv}, push,
                 uint64_t(push.chunks) * uint64_t(heads));
    return out;
}

}  // namespace pg::nn::ops

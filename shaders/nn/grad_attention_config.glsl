// Push constants and tunables of the window-attention backward (nn/train/grad_attention.cpp and
// shaders/nn/grad_attention_*), shared by C++ and GLSL: one definition, no drift.
#ifndef PG_GRAD_ATTENTION_CONFIG_GLSL
#define PG_GRAD_ATTENTION_CONFIG_GLSL

#ifdef __cplusplus
#include <cstdint>
namespace pg::nn::grad::gpu {
using uint = uint32_t;
#endif

// GPU kernels: invocations per workgroup, one (head, serialized position) each.
#define PG_GRAD_ATTN_THREADS 64
// CPU kernels (grad_attention_cpu_*): PG_ATTN_CPU_THREADS invocations, each with this many
// positions of one window; their registers (4 x head_dim floats a key) stay near 256 floats.
#define PG_GRAD_ATTN_CPU_ROWS(d) (64 / (d))

struct GradAttentionPush {
    uint rows;      // N
    uint clouds;    // B: offsets holds B + 1 entries
    uint heads;     // H
    uint channels;  // C = H * head_dim
    uint window;    // K: the patch size
    uint head_dim;  // D
    float scale2;   // softmax scale times log2(e): logits in base 2 for exp2
    float scale;    // softmax scale: the chain rule's factor on dq, dk
    uint windows;   // CPU kernels: windows numbered floor(offsets[b] / K) + b + local window
    uint subs;      // CPU kernels: blocks per window
    uint pad0, pad1;
};

#ifdef __cplusplus
}  // namespace pg::nn::grad::gpu
#endif

#endif

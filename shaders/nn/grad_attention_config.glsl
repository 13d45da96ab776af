// Push constants and tunables of the window-attention backward (nn/train/grad_attention.cpp and
// shaders/nn/grad_attention_*), shared by C++ and GLSL: one definition, no drift.
#ifndef PG_GRAD_ATTENTION_CONFIG_GLSL
#define PG_GRAD_ATTENTION_CONFIG_GLSL

#ifdef __cplusplus
#include <cstdint>
namespace pg::nn::grad::gpu {
using uint = uint32_t;
#endif

// Invocations per workgroup: one (head, serialized position) each.
#define PG_GRAD_ATTN_THREADS 64

struct GradAttentionPush {
    uint rows;      // N
    uint clouds;    // B: offsets holds B + 1 entries
    uint heads;     // H
    uint channels;  // C = H * head_dim
    uint window;    // K: the patch size
    uint head_dim;  // D
    float scale2;   // softmax scale times log2(e): logits in base 2 for exp2
    float scale;    // softmax scale: the chain rule's factor on dq, dk
};

#ifdef __cplusplus
}  // namespace pg::nn::grad::gpu
#endif

#endif

// Tunables and the push-constant layout shared by nn/ops/attention.cpp (C++) and the
// shaders/nn/attention_*.comp kernels (GLSL): one definition, no drift.
#ifndef PG_ATTENTION_CONFIG_GLSL
#define PG_ATTENTION_CONFIG_GLSL

#ifdef __cplusplus
#include <cstdint>
namespace pg::nn::gpu {
using uint = uint32_t;
#endif

// A workgroup takes a block of THREADS * ROWS serialized positions of one head; each
// invocation keeps ROWS queries and their accumulators in registers.
//
// GPUs: one query per invocation, many invocations.
#define PG_ATTN_GPU_THREADS 64
#define PG_ATTN_GPU_ROWS 1
// CPU drivers (lavapipe): every load is a per-lane scalar loop, so each loaded key/value
// element must serve many queries, and one SIMD-wide invocation group per workgroup makes
// shared-memory staging pointless. Head size 16 (PTv3's everywhere) gets 16 queries per
// invocation; the others get half the unrolled code, trading speed for compile time.
#define PG_ATTN_CPU_THREADS 8
#define PG_ATTN_CPU_ROWS(d) ((d) == 16 ? 16 : 128 / (d))
// nn/attention_gather: invocations per workgroup, one vec4 each.
#define PG_ATTN_GATHER_THREADS 256
// GPU kernel: keys per shared-memory tile (K and V: 2 * tile * head_dim floats, 16 KiB at
// head_dim 64). Both kernels take keys in groups with one softmax rescale per group.
#define PG_ATTN_TILE 32
#define PG_ATTN_GROUP 4

struct AttentionPush {
    uint rows;      // N: points, rows of qkv and of the output
    uint clouds;    // B: offsets holds B + 1 entries
    uint heads;     // H
    uint channels;  // C = H * head_dim
    uint window;    // K: the patch size, keys per window
    uint chunks;    // query blocks per head (workgroups = chunks * heads)
    float scale;    // softmax scale times log2(e): the kernel uses exp2
    uint head_dim;  // D = C / H
};

#ifdef __cplusplus
}  // namespace pg::nn::gpu
#endif

#endif

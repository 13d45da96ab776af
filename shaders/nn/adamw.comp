#version 450
// One AdamW step per element, in PyTorch's order: decoupled decay p *= 1 - lr*wd, moments,
// then p -= (lr / bias1) * m / (sqrt(v) / sqrt(bias2) + eps).
// Up to PG_ADAMW_SETS parameter tensors per dispatch, each with its own seven bindings (28 of
// the 32 push descriptors every device has): a model's hundreds of small tensors in tens of
// dispatches, whose fixed cost dominates on CPU devices. Tensor s takes the workgroups from
// first_group[s]; unused sets are bound to set 0's buffers with no workgroups.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/grad_shared.glsl"

layout(local_size_x = PG_GRAD_THREADS) in;
layout(push_constant) uniform PushBlock { AdamWPush pc; };

// Per tensor: p, g, m and v read through texel buffers (a vector gather on CPU drivers, where a
// storage-buffer load is a loop over the lanes), p, m and v written through storage buffers.
// Each element is read and then written by one invocation only, so the two views of a buffer
// never race.
#define PG_ADAMW_BINDINGS(s)                                                                \
    layout(binding = 7 * s, r32f) readonly uniform imageBuffer p_in##s;                     \
    layout(binding = 7 * s + 1, r32f) readonly uniform imageBuffer g_in##s;                 \
    layout(binding = 7 * s + 2, r32f) readonly uniform imageBuffer m_in##s;                 \
    layout(binding = 7 * s + 3, r32f) readonly uniform imageBuffer v_in##s;                 \
    layout(std430, binding = 7 * s + 4) writeonly buffer Params##s { float p##s[]; };       \
    layout(std430, binding = 7 * s + 5) writeonly buffer First##s { float m##s[]; };        \
    layout(std430, binding = 7 * s + 6) writeonly buffer Second##s { float v##s[]; };
PG_ADAMW_BINDINGS(0)
PG_ADAMW_BINDINGS(1)
PG_ADAMW_BINDINGS(2)
PG_ADAMW_BINDINGS(3)

#define PG_ADAMW_STEP(s)                                                                     \
    {                                                                                        \
        float grad = imageLoad(g_in##s, int(i)).x;                                           \
        float param = imageLoad(p_in##s, int(i)).x * (1.0 - pc.lr * pc.weight_decay);        \
        float mi = pc.beta1 * imageLoad(m_in##s, int(i)).x + (1.0 - pc.beta1) * grad;        \
        float vi = pc.beta2 * imageLoad(v_in##s, int(i)).x + (1.0 - pc.beta2) * grad * grad; \
        m##s[i] = mi;                                                                        \
        v##s[i] = vi;                                                                        \
        p##s[i] = param - (pc.lr / pc.bias1) * mi / (sqrt(vi) / pc.bias2_sqrt + pc.eps);     \
    }

void main() {
    const uint group = pg_group_index();
    uint s = 0u;
    for (uint t = 1u; t < PG_ADAMW_SETS; ++t)
        if (group >= pc.first_group[t]) s = t;
    const uint i = (group - pc.first_group[s]) * gl_WorkGroupSize.x + gl_LocalInvocationIndex;
    if (i >= pc.count[s]) return;
    switch (s) {
    case 0u: PG_ADAMW_STEP(0) break;
    case 1u: PG_ADAMW_STEP(1) break;
    case 2u: PG_ADAMW_STEP(2) break;
    default: PG_ADAMW_STEP(3) break;
    }
}

#version 450
// One AdamW step per element, in PyTorch's order: decoupled decay p *= 1 - lr*wd, moments,
// then p -= (lr / bias1) * m / (sqrt(v) / sqrt(bias2) + eps).
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/grad_shared.glsl"

layout(local_size_x = PG_GRAD_THREADS) in;
layout(std430, binding = 0) buffer Params { float p[]; };
layout(std430, binding = 1) readonly buffer Grads { float g[]; };
layout(std430, binding = 2) buffer First { float m[]; };
layout(std430, binding = 3) buffer Second { float v[]; };
layout(push_constant) uniform PushBlock { AdamWPush pc; };

void main() {
    uint i = pg_global_index();
    if (i >= pc.count) return;
    float grad = g[i];
    float param = p[i] * (1.0 - pc.lr * pc.weight_decay);
    float mi = pc.beta1 * m[i] + (1.0 - pc.beta1) * grad;
    float vi = pc.beta2 * v[i] + (1.0 - pc.beta2) * grad * grad;
    m[i] = mi;
    v[i] = vi;
    p[i] = param - (pc.lr / pc.bias1) * mi / (sqrt(vi) / pc.bias2_sqrt + pc.eps);
}

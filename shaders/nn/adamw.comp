#version 450
// One AdamW step per element, in PyTorch's order: decoupled decay p *= 1 - lr*wd, moments,
// then p -= (lr / bias1) * m / (sqrt(v) / sqrt(bias2) + eps).
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"

layout(local_size_x = 256) in;
layout(std430, binding = 0) buffer Params { float p[]; };
layout(std430, binding = 1) readonly buffer Grads { float g[]; };
layout(std430, binding = 2) buffer First { float m[]; };
layout(std430, binding = 3) buffer Second { float v[]; };
layout(push_constant) uniform Push {
    uint count;
    float lr, beta1, beta2, eps, weight_decay, bias1, bias2_sqrt;
};

void main() {
    uint i = pg_global_index();
    if (i >= count) return;
    float grad = g[i];
    float param = p[i] * (1.0 - lr * weight_decay);
    float mi = beta1 * m[i] + (1.0 - beta1) * grad;
    float vi = beta2 * v[i] + (1.0 - beta2) * grad * grad;
    m[i] = mi;
    v[i] = vi;
    p[i] = param - (lr / bias1) * mi / (sqrt(vi) / bias2_sqrt + eps);
}

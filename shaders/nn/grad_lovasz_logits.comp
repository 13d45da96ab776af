#version 450
// Lovasz-softmax, pass 4, per row: d loss / d p_c = weight_c * sign(p_c - [label == c]), then
// through the softmax: dlogits_k = p_k (dp_k - sum_c dp_c p_c). Rows not counted get 0.
// Scaled by pc.scale (the loss weight); invocation 0 scales the summed loss the same way.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/grad_shared.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer LogitBuf { float logits[]; };
layout(std430, binding = 1) readonly buffer LabelBuf { int labels[]; };
layout(std430, binding = 2) readonly buffer WeightBuf { float weights[]; };
layout(std430, binding = 3) readonly buffer SumBuf { float sums[]; };
layout(std430, binding = 4) writeonly buffer DBuf { float dlogits[]; };
layout(std430, binding = 5) writeonly buffer LossBuf { float loss[]; };
layout(push_constant) uniform PushBlock { LovaszPush pc; };
#include "nn/grad_lovasz_softmax.glsl"

void main() {
    const uint r = pg_global_index();
    if (r == 0u) loss[0] = sums[0] * pc.scale;
    if (r >= pc.rows) return;
    const uint base = r * pc.classes;
    const int label = labels[r];
    if (!lovasz_counted(label)) {
        for (uint k = 0u; k < pc.classes; ++k) dlogits[base + k] = 0.0;
        return;
    }
    float mx = logits[base];
    for (uint k = 1u; k < pc.classes; ++k) mx = max(mx, logits[base + k]);
    float s = 0.0;
    for (uint k = 0u; k < pc.classes; ++k) s += exp(logits[base + k] - mx);
    float dot_dp_p = 0.0;
    for (uint k = 0u; k < pc.classes; ++k) {
        const float p = exp(logits[base + k] - mx) / s;
        const float dp = weights[k * pc.rows + r] * (label == int(k) ? -1.0 : 1.0);
        dot_dp_p += dp * p;
    }
    for (uint k = 0u; k < pc.classes; ++k) {
        const float p = exp(logits[base + k] - mx) / s;
        const float dp = weights[k * pc.rows + r] * (label == int(k) ? -1.0 : 1.0);
        dlogits[base + k] = pc.scale * p * (dp - dot_dp_p);
    }
}

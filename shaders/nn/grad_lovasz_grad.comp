#version 450
// Lovasz-softmax, pass 3, per sorted entry j: with n counted rows, class c owns sorted entries
// [c n, (c + 1) n); at rank i in it, with g = the class's foreground count and f = foreground
// among its first i + 1 entries, J_i = 1 - (g - f) / (g + i + 1 - f) (Jaccard loss of predicting
// the first i + 1 as the class). The entry's weight is J_i - J_(i-1) (J_-1 = 0), divided by the
// number of classes present (g > 0; absent classes weigh 0). Writes the loss term
// weight * error per sorted entry and the weight per entry (unsorted, for the logits pass).
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/grad_shared.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer LogitBuf { float logits[]; };
layout(std430, binding = 1) readonly buffer LabelBuf { int labels[]; };
layout(std430, binding = 2) readonly buffer OrderBuf { int order[]; };
layout(std430, binding = 3) readonly buffer CumBuf { uint cum[]; };  // exclusive scan of fg, [entries + 1]
layout(std430, binding = 4) readonly buffer CountBuf { uint counts[]; };
layout(std430, binding = 5) writeonly buffer TermBuf { float terms[]; };
layout(std430, binding = 6) writeonly buffer WeightBuf { float weights[]; };
layout(push_constant) uniform PushBlock { LovaszPush pc; };
#include "nn/grad_lovasz_softmax.glsl"

float jaccard_loss(float g, float f, float taken) { return 1.0 - (g - f) / (g + taken - f); }

void main() {
    const uint j = pg_global_index();
    const uint entries = pc.rows * pc.classes;
    if (j >= entries) return;
    const uint n = counts[0];
    const uint e = uint(order[j]);
    if (j >= n * pc.classes) {  // rows not counted
        terms[j] = 0.0;
        weights[e] = 0.0;
        return;
    }
    uint present = 0u;
    for (uint k = 0u; k < pc.classes; ++k) present += cum[(k + 1u) * n] > cum[k * n] ? 1u : 0u;
    const uint c = j / n, i = j - c * n, start = c * n;
    const float g = float(cum[start + n] - cum[start]);
    const uint fg_here = cum[j + 1u] - cum[j];
    const float f_before = float(cum[j] - cum[start]);
    float w = 0.0;
    if (g > 0.0) {
        w = jaccard_loss(g, f_before + float(fg_here), float(i + 1u));
        if (i > 0u) w -= jaccard_loss(g, f_before, float(i));
        w /= float(present);
    }
    const uint r = e - c * pc.rows;
    const float error = abs(float(fg_here) - lovasz_probability(r, c));
    terms[j] = w * error;
    weights[e] = w;
}

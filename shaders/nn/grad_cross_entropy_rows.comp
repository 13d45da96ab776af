#version 450
// Softmax cross-entropy per row: loss_r = logsumexp(logits[r]) - logits[r, label] and the
// unscaled gradient softmax(logits[r]) - onehot(label). Rows with the ignored label, or with a
// label outside [0, classes) (counted as bad), get loss 0 and a zero gradient.
// vals[r] = (loss, counted, bad) for the deterministic column sums.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/grad_shared.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer LogitBuf { float logits[]; };
layout(std430, binding = 1) readonly buffer LabelBuf { int labels[]; };
layout(std430, binding = 2) writeonly buffer DBuf { float dlogits[]; };
layout(std430, binding = 3) writeonly buffer ValBuf { float vals[]; };
layout(push_constant) uniform PushBlock { CrossEntropyPush pc; };

void main() {
    const uint r = pg_global_index();
    if (r >= pc.rows) return;
    const uint base = r * pc.classes;
    const int label = labels[r];
    const bool ignored = label == pc.ignore_label;
    const bool bad = !ignored && (label < 0 || label >= int(pc.classes));
    if (ignored || bad) {
        for (uint k = 0u; k < pc.classes; ++k) dlogits[base + k] = 0.0;
        vals[r * PG_CE_VALUES + PG_CE_LOSS] = 0.0;
        vals[r * PG_CE_VALUES + PG_CE_COUNTED] = 0.0;
        vals[r * PG_CE_VALUES + PG_CE_BAD] = bad ? 1.0 : 0.0;
        return;
    }
    float mx = logits[base];
    for (uint k = 1u; k < pc.classes; ++k) mx = max(mx, logits[base + k]);
    float s = 0.0;
    for (uint k = 0u; k < pc.classes; ++k) s += exp(logits[base + k] - mx);
    const float inv = 1.0 / s;
    for (uint k = 0u; k < pc.classes; ++k)
        dlogits[base + k] = exp(logits[base + k] - mx) * inv - (int(k) == label ? 1.0 : 0.0);
    vals[r * PG_CE_VALUES + PG_CE_LOSS] = (mx - logits[base + uint(label)]) + log(s);
    vals[r * PG_CE_VALUES + PG_CE_COUNTED] = 1.0;
    vals[r * PG_CE_VALUES + PG_CE_BAD] = 0.0;
}

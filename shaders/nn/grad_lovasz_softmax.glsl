// Shared by the nn/grad_lovasz_* passes (include after the `logits` buffer and the push block
// `pc`): whether a row takes part, and a row's softmax probability of one class.
#ifndef PG_NN_GRAD_LOVASZ_SOFTMAX_GLSL
#define PG_NN_GRAD_LOVASZ_SOFTMAX_GLSL

// Rows labelled with the ignored label or outside [0, classes) are left out.
bool lovasz_counted(int label) { return label != pc.ignore_label && label >= 0 && label < int(pc.classes); }

// Same arithmetic as nn/grad_cross_entropy_rows (max shift, then exp / sum).
float lovasz_probability(uint row, uint cls) {
    const uint base = row * pc.classes;
    float mx = logits[base];
    for (uint k = 1u; k < pc.classes; ++k) mx = max(mx, logits[base + k]);
    float s = 0.0;
    for (uint k = 0u; k < pc.classes; ++k) s += exp(logits[base + k] - mx);
    return exp(logits[base + cls] - mx) / s;
}

#endif

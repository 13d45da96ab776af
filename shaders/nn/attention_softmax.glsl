// Binding-free piece of the window-attention kernels, forward and backward: the online
// softmax step.
#ifndef PG_ATTENTION_SOFTMAX_GLSL
#define PG_ATTENTION_SOFTMAX_GLSL
#include "nn/attention_config.glsl"

// Below any real logit, yet finite: exp2(kNone - m) is 0 without inf - inf.
const float kNone = -3.0e38;

// Online softmax over one group of base-2 logits: turns s into weights relative to the new
// running max m, adds them to the running sum l, and returns the factor that rescales what was
// accumulated under the old max.
float softmax_group(inout float m, inout float l, inout float s[PG_ATTN_GROUP]) {
    float mt = m;
    [[unroll]] for (uint j = 0u; j < PG_ATTN_GROUP; ++j) mt = max(mt, s[j]);
    const float alpha = exp2(m - mt);
    float sum = 0.0;
    [[unroll]] for (uint j = 0u; j < PG_ATTN_GROUP; ++j) {
        s[j] = exp2(s[j] - mt);
        sum += s[j];
    }
    m = mt;
    l = l * alpha + sum;
    return alpha;
}

#endif

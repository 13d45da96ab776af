#version 450
// Window-attention backward, dq and softmax stats, head dimension 16 (nn/train/grad_attention.cpp).
#extension GL_GOOGLE_include_directive : require
#define PG_ATTN_D 16
#include "nn/grad_attention_dq.glsl"

#version 450
// Serialized window attention, head dimension 8, for GPUs (nn/ops/attention.cpp).
#extension GL_GOOGLE_include_directive : require
#define PG_ATTN_D 8
#include "nn/attention_gpu.glsl"

#version 450
// Serialized window attention, head dimension 16, for GPUs (nn/ops/attention.cpp).
#extension GL_GOOGLE_include_directive : require
#define PG_ATTN_D 16
#include "nn/attention_gpu.glsl"

#version 450
// Serialized window attention, head dimension 32, for CPU drivers (nn/ops/attention.cpp).
#extension GL_GOOGLE_include_directive : require
#define PG_ATTN_D 32
#include "nn/attention_cpu.glsl"

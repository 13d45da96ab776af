#version 450
// One tap of a sparse-convolution rulebook on GPUs: see gemm_tiled.glsl.
#extension GL_GOOGLE_include_directive : require
#define RULEBOOK 1
#include "nn/gemm_tiled.glsl"

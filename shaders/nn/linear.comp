#version 450
// Linear and sparse convolution on GPUs: see gemm_tiled.glsl.
#extension GL_GOOGLE_include_directive : require
#include "nn/gemm_tiled.glsl"

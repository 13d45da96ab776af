#version 450
// gemm_lanes.glsl over a sparse-convolution rulebook, one tap or all taps a dispatch (TAPS 0 / 1: shaders/CMakeLists.txt builds both): 32 pairs per workgroup, depth chunks of 32.
#extension GL_GOOGLE_include_directive : require
#define WG 32u
#define KC 32u
#define A_VEC 1
#define Y_VEC 1
#define GELU 0
#define RULEBOOK 1
#include "nn/gemm_lanes.glsl"

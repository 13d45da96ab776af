#version 450
// gemm_lanes.glsl over a sparse-convolution rulebook, one tap or all taps a dispatch (TAPS 0 / 1: shaders/CMakeLists.txt builds both): 128 pairs per workgroup, depth chunks of 16.
#extension GL_GOOGLE_include_directive : require
#define WG 128u
#define KC 16u
#define A_VEC 1
#define Y_VEC 1
#define GELU 0
#define RULEBOOK 1
#include "nn/gemm_lanes.glsl"

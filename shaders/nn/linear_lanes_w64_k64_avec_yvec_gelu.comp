#version 450
// gemm_lanes.glsl with 64 rows per workgroup, depth chunks of 64, 8-wide A/W loads, 8-wide y rows, GELU before the store.
#extension GL_GOOGLE_include_directive : require
#define WG 64u
#define KC 64u
#define A_VEC 1
#define Y_VEC 1
#define GELU 1
#include "nn/gemm_lanes.glsl"

#version 450
// gemm_lanes.glsl with 256 rows per workgroup, depth chunks of 32, 8-wide A/W loads, 8-wide y rows.
#extension GL_GOOGLE_include_directive : require
#define WG 256u
#define KC 32u
#define A_VEC 1
#define Y_VEC 1
#define GELU 0
#include "nn/gemm_lanes.glsl"

#version 450
// gemm_lanes.glsl with 256 rows per workgroup, depth chunks of 64, 8-wide A/W loads with a
// neighbour lookup per 8 columns (gathered rows of cin % 8 == 0), 8-wide y rows.
#extension GL_GOOGLE_include_directive : require
#define WG 256u
#define KC 64u
#define A_VEC 1
#define A_SEG 8u
#define Y_VEC 1
#define GELU 0
#include "nn/gemm_lanes.glsl"

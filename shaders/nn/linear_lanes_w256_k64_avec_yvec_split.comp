#version 450
// gemm_lanes.glsl with 256 rows per workgroup, depth chunks of 64, 8-wide A/W loads and y rows, the depth split over the dispatch's workgroups.
#extension GL_GOOGLE_include_directive : require
#define WG 256u
#define KC 64u
#define A_VEC 1
#define Y_VEC 1
#define GELU 0
#define SPLIT 1
#include "nn/gemm_lanes.glsl"

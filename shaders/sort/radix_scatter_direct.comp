#version 450
// Radix sort pass, step 2, for CPU devices: see sort/radix_scatter.glsl.
#extension GL_GOOGLE_include_directive : require
#define PG_RADIX_EXCHANGE 0
#include "sort/radix_scatter.glsl"

#version 450
// k-means assignment for points of 9 floats (compress/kmeans_assign.glsl).
#extension GL_GOOGLE_include_directive : require
#include "compress/kmeans_shared.h"
#define DIMS 9
#define BLOCK PG_KMEANS_BLOCK_D9
#define ROWS PG_KMEANS_ROWS_D9
#include "compress/kmeans_assign.glsl"

#version 450
// k-means assignment for points of 45 floats (compress/kmeans_assign.glsl).
#extension GL_GOOGLE_include_directive : require
#include "compress/kmeans_shared.h"
#define DIMS 45
#define BLOCK PG_KMEANS_BLOCK_D45
#define ROWS PG_KMEANS_ROWS_D45
#include "compress/kmeans_assign.glsl"

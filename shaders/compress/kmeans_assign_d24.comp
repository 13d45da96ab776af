#version 450
// k-means assignment for points of 24 floats (compress/kmeans_assign.glsl).
#extension GL_GOOGLE_include_directive : require
#include "compress/kmeans_shared.h"
#define DIMS 24
#define BLOCK PG_KMEANS_BLOCK_D24
#define ROWS PG_KMEANS_ROWS_D24
#include "compress/kmeans_assign.glsl"

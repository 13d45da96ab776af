#version 450
// Distance-bounded label rasterization, one window of every tile's list per dispatch (segment/label_paper.glsl).
#extension GL_GOOGLE_include_directive : require
#define PG_TILE_WINDOWS 1
#include "segment/label_paper.glsl"

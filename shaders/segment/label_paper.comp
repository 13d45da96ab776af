#version 450
// Distance-bounded label rasterization of every tile's whole list in one dispatch (segment/label_paper.glsl).
#extension GL_GOOGLE_include_directive : require
#define PG_TILE_WINDOWS 0
#include "segment/label_paper.glsl"

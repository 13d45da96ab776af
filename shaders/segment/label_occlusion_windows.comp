#version 450
// Occlusion-aware label rasterization, one window of every tile's list per dispatch (segment/label_occlusion.glsl; built per PG_RUN_ROWS).
#extension GL_GOOGLE_include_directive : require
#define PG_TILE_WINDOWS 1
#include "segment/label_occlusion.glsl"

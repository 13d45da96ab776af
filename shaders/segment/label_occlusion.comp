#version 450
// Occlusion-aware label rasterization of every tile's whole list in one dispatch (segment/label_occlusion.glsl; built per PG_RUN_ROWS).
#extension GL_GOOGLE_include_directive : require
#define PG_TILE_WINDOWS 0
#include "segment/label_occlusion.glsl"

#version 450
// Front-to-back blending of every tile's whole list in one dispatch (render/blend.glsl; built per PG_RUN_ROWS).
#extension GL_GOOGLE_include_directive : require
#define PG_TILE_WINDOWS 0
#include "render/blend.glsl"

#version 450
// Front-to-back blending, one window of every tile's list per dispatch (render/blend.glsl; built per PG_RUN_ROWS).
#extension GL_GOOGLE_include_directive : require
#define PG_TILE_WINDOWS 1
#include "render/blend.glsl"

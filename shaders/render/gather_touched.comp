#version 450
// Tile counts in depth order, so the prefix sum lays out each Gaussian's keys front to back.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "render/render_shared.h"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Frame { FrameParams frame; };
layout(std430, binding = 1) readonly buffer Order { uint order[]; };
layout(std430, binding = 2) readonly buffer Touched { uint touched[]; };
layout(std430, binding = 3) writeonly buffer Sorted { uint touched_sorted[]; };

void main() {
    uint k = pg_global_index();
    if (k < frame.scene.x) touched_sorted[k] = touched[order[k]];
}

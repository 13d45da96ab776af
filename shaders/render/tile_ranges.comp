#version 450
// Finds where each tile's run starts and ends in the sorted keys.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "render/render_shared.h"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Frame { FrameParams frame; };
layout(std430, binding = 1) readonly buffer Counts { uint counts[]; };
layout(std430, binding = 2) readonly buffer Keys { uint keys[]; };   // tile ids, sorted
layout(std430, binding = 3) buffer Ranges { uvec2 ranges[]; };          // zeroed before

void main() {
    uint i = pg_global_index();
    uint n = min(counts[0], frame.capacity.x);
    if (i >= n) return;
    uint tile = keys[i];
    if (tile >= frame.size.z * frame.size.w) return;  // padding from emit_keys
    if (i == 0u || keys[i - 1u] != tile) ranges[tile].x = i;
    if (i == n - 1u || keys[i + 1u] != tile) ranges[tile].y = i + 1u;
}

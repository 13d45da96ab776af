#version 450
// Finds where each tile's run starts and ends in the sorted keys.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "render/render_shared.h"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Frame { FrameParams frame; };
layout(std430, binding = 1) readonly buffer Counts { uint counts[]; };
layout(std430, binding = 2) readonly buffer Keys { uint keys[]; };   // tile ids (or depth bits), sorted
layout(std430, binding = 3) buffer Ranges { uvec2 ranges[]; };          // zeroed before

void main() {
    uint i = pg_global_index();
    uint n = min(counts[0], frame.capacity.x);
    if (i >= n) return;
    if ((frame.capacity.w & kFrameDepthKeys) != 0u) {
        // One tile, the window's; positive depths sort before the padding's all-ones keys.
        if (keys[i] == 0xFFFFFFFFu) return;
        uint tile = (frame.window.y / kTileSize) * frame.size.z + frame.window.x / kTileSize;
        if (i == 0u) ranges[tile].x = 0u;
        if (i == n - 1u || keys[i + 1u] == 0xFFFFFFFFu) ranges[tile].y = i + 1u;
        return;
    }
    uint tile = keys[i];
    if (tile >= frame.size.z * frame.size.w) return;  // padding from emit_keys
    if (i == 0u || keys[i - 1u] != tile) ranges[tile].x = i;
    if (i == n - 1u || keys[i + 1u] != tile) ranges[tile].y = i + 1u;
}

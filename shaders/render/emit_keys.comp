#version 450
// Writes one (tile, gaussian) pair per tile a Gaussian touches. Thread k handles the k-th
// nearest Gaussian at the offset of the prefix sum in depth order, so a stable sort on the
// tile id alone leaves each tile's Gaussians front to back, ties by index as in the reference.
// With kFrameDepthKeys (a window inside one tile) the order is the index order and the key the
// depth, so one stable sort of the keys gives the same list.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "render/render_shared.h"
#include "render/tile_test.glsl"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Frame { FrameParams frame; };
layout(std430, binding = 1) readonly buffer Splats { Splat splats[]; };
layout(std430, binding = 2) readonly buffer Order { uint order[]; };
layout(std430, binding = 3) readonly buffer Touched { uint touched_sorted[]; };
layout(std430, binding = 4) readonly buffer Offsets { uint offsets[]; };
layout(std430, binding = 5) readonly buffer Rects { uvec2 rects[]; };
layout(std430, binding = 6) writeonly buffer Keys { uint keys[]; };     // tile id, or depth bits
layout(std430, binding = 7) writeonly buffer Values { uint values[]; }; // Gaussian index

void main() {
    uint k = pg_global_index();
    if (k >= frame.scene.x || touched_sorted[k] == 0u) return;
    uint i = order[k];
    uint out_index = offsets[k];
    uint out_end = min(out_index + touched_sorted[k], frame.capacity.x);  // past capacity: the host renders again
    Splat sp = splats[i];
    uvec2 r = rects[i];
    uint x0 = r.x & 0xFFFFu, y0 = r.x >> 16, x1 = r.y & 0xFFFFu, y1 = r.y >> 16;
    bool test = (x1 - x0 + 1u) * (y1 - y0 + 1u) > 2u;  // the same rule as preprocess
    bool depth_keys = (frame.capacity.w & kFrameDepthKeys) != 0u;
    uint padding = depth_keys ? 0xFFFFFFFFu : frame.size.z * frame.size.w;
    for (uint ty = y0; ty <= y1; ++ty)
        for (uint tx = x0; tx <= x1; ++tx) {
            if (test && !pg_ellipse_hits_tile(sp.mean, sp.conic.xyz, sp.conic.w, uvec2(tx, ty), frame.size.xy)) continue;
            if (out_index >= out_end) return;
            keys[out_index] = depth_keys ? floatBitsToUint(sp.depth) : ty * frame.size.z + tx;
            values[out_index] = i;
            ++out_index;
        }
    // Should the tile test ever disagree with preprocess's count, the unused slots get a
    // key past every real one, which tile_ranges ignores.
    for (; out_index < out_end; ++out_index) {
        keys[out_index] = padding;
        values[out_index] = i;
    }
}

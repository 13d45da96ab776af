#version 450
// Writes one (tile | depth, gaussian) pair per tile a Gaussian touches, at the offsets of
// the prefix sum over touched counts: keys come out in Gaussian order, so the stable sort
// breaks depth ties by index, as the CPU reference does.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "render/render_shared.h"
#include "render/tile_test.glsl"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Frame { FrameParams frame; };
layout(std430, binding = 1) readonly buffer Splats { Splat splats[]; };
layout(std430, binding = 2) readonly buffer Touched { uint touched[]; };
layout(std430, binding = 3) readonly buffer Offsets { uint offsets[]; };
layout(std430, binding = 4) readonly buffer Rects { uvec2 rects[]; };
layout(std430, binding = 5) writeonly buffer Keys { uvec2 keys[]; };     // (depth bits, tile)
layout(std430, binding = 6) writeonly buffer Values { uint values[]; };

void main() {
    uint i = pg_global_index();
    if (i >= frame.scene.x || touched[i] == 0u) return;
    uint out_index = offsets[i];
    uint out_end = out_index + touched[i];
    uint capacity = frame.capacity.x;
    // Depths are > near > 0, so their float bits order like the floats.
    uint depth_bits = floatBitsToUint(splats[i].depth);  // read once below too
    uvec2 r = rects[i];
    uint x0 = r.x & 0xFFFFu, y0 = r.x >> 16, x1 = r.y & 0xFFFFu, y1 = r.y >> 16;
    Splat sp = splats[i];
    vec3 q = sp.conic.xyz;
    bool test = (x1 - x0 + 1u) * (y1 - y0 + 1u) > 2u;  // the same rule as preprocess
    for (uint ty = y0; ty <= y1; ++ty)
        for (uint tx = x0; tx <= x1; ++tx) {
            if (test && !pg_ellipse_hits_tile(sp.mean, q, sp.conic.w, uvec2(tx, ty), frame.size.xy)) continue;
            if (out_index >= min(out_end, capacity)) return;  // overflow: the host grows the buffers and renders again
            keys[out_index] = uvec2(depth_bits, ty * frame.size.z + tx);
            values[out_index] = i;
            ++out_index;
        }
    // Should the tile test ever disagree with preprocess's count, the unused slots get a
    // tile id past the last one, which tile_ranges ignores.
    for (; out_index < min(out_end, capacity); ++out_index) {
        keys[out_index] = uvec2(0xFFFFFFFFu, frame.size.z * frame.size.w);
        values[out_index] = i;
    }
}

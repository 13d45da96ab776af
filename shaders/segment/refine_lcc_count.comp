#version 450
// Largest component, step 1 of 4: component sizes at the roots. refine_cc_local left each
// tile-local root's pixel count in `sizes`; the other tile-local roots add theirs to their
// global root (one atomic per tile-local component, not per pixel).
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/refine_shared.h"

layout(local_size_x = PG_REFINE_THREADS) in;
layout(std430, binding = 0) readonly buffer Parent { uint parent[]; };
layout(std430, binding = 1) buffer Sizes { uint sizes[]; };
layout(push_constant) uniform Push { PixelPush pc; };

void main() {
    const uint p = pg_global_index();
    if (p >= pc.width * pc.height) return;
    const uint root = parent[p];
    if (root == p) return;  // a global root: its own count is in place, others add to it
    const uint n = sizes[p];
    if (n != 0u) atomicAdd(sizes[root], n);
}

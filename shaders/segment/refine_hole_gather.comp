#version 450
// Hole filling, step 1 of 2: every 0-pixel tells its component's root (4-connected 0-pixels)
// whether it lies on the image border (lowest = 0) and which instances are its 4-neighbours
// (lowest and highest). Only pixels on a component's outline do any atomics.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/refine_shared.h"

layout(local_size_x = PG_REFINE_THREADS) in;
layout(std430, binding = 0) readonly buffer Labels { uint labels[]; };
layout(std430, binding = 1) readonly buffer Parent { uint parent[]; };
layout(std430, binding = 2) coherent buffer Lowest { uint lowest[]; };    // starts at ~0
layout(std430, binding = 3) coherent buffer Highest { uint highest[]; };  // starts at 0
layout(push_constant) uniform Push { PixelPush pc; };

void main() {
    const uint p = pg_global_index();
    const uint w = pc.width, h = pc.height;
    if (p >= w * h || labels[p] != 0u) return;
    const uint x = p % w, y = p / w;
    uint lo = 0xFFFFFFFFu, hi = 0u;
    if (x == 0u || y == 0u || x + 1u == w || y + 1u == h) lo = 0u;  // touches the border
    if (x > 0u && labels[p - 1u] != 0u) { lo = min(lo, labels[p - 1u]); hi = max(hi, labels[p - 1u]); }
    if (x + 1u < w && labels[p + 1u] != 0u) { lo = min(lo, labels[p + 1u]); hi = max(hi, labels[p + 1u]); }
    if (y > 0u && labels[p - w] != 0u) { lo = min(lo, labels[p - w]); hi = max(hi, labels[p - w]); }
    if (y + 1u < h && labels[p + w] != 0u) { lo = min(lo, labels[p + w]); hi = max(hi, labels[p + w]); }
    if (lo == 0xFFFFFFFFu && hi == 0u) return;  // inside the component: nothing to tell
    const uint root = parent[p];
    // The stored values only move towards the final one: skip atomics that cannot change it.
    if (lowest[root] > lo) atomicMin(lowest[root], lo);
    if (highest[root] < hi) atomicMax(highest[root], hi);
}

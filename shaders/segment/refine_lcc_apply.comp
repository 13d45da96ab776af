#version 450
// Largest component, step 4 of 4: pixels of every other component become 0. src may be dst.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/refine_shared.h"

layout(local_size_x = PG_REFINE_THREADS) in;
layout(std430, binding = 0) readonly buffer Src { uint src[]; };
layout(std430, binding = 1) writeonly buffer Dst { uint dst[]; };
layout(std430, binding = 2) readonly buffer Parent { uint parent[]; };
layout(std430, binding = 3) readonly buffer Slots { uint slots[]; };
layout(std430, binding = 4) readonly buffer BestRoot { uint best_root[]; };
layout(push_constant) uniform Push { PixelPush pc; };

void main() {
    const uint p = pg_global_index();
    if (p >= pc.width * pc.height) return;
    uint label = src[p];
    if (label != 0u) {
        const uint root = parent[p];
        if (best_root[slots[root]] != root) label = 0u;
    }
    dst[p] = label;
}

#version 450
// Largest component, step 2 of 4: every component root finds (or claims) its instance's slot
// and raises the instance's largest size.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/refine_shared.h"
#include "segment/refine_lcc_table.glsl"

layout(local_size_x = PG_REFINE_THREADS) in;
layout(std430, binding = 0) readonly buffer Labels { uint labels[]; };
layout(std430, binding = 1) readonly buffer Parent { uint parent[]; };
layout(std430, binding = 2) readonly buffer Sizes { uint sizes[]; };
layout(std430, binding = 3) writeonly buffer Slots { uint slots[]; };    // per root
layout(std430, binding = 4) coherent buffer Keys { uint keys[]; };       // starts at 0
layout(std430, binding = 5) coherent buffer BestSize { uint best_size[]; };  // starts at 0
layout(push_constant) uniform Push { PixelPush pc; };

void main() {
    const uint p = pg_global_index();
    if (p >= pc.width * pc.height) return;
    const uint label = labels[p];
    if (label == 0u || parent[p] != p) return;
    uint slot = lcc_hash(label) & pc.table_mask;
    for (;;) {
        uint key = keys[slot];
        if (key == 0u) key = atomicCompSwap(keys[slot], 0u, label);
        if (key == 0u || key == label) break;
        slot = (slot + 1u) & pc.table_mask;
    }
    slots[p] = slot;
    const uint n = sizes[p];
    if (best_size[slot] < n) atomicMax(best_size[slot], n);
}

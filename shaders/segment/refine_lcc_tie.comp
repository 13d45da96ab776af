#version 450
// Largest component, step 3 of 4: among an instance's components of the largest size, the
// one with the smallest root (its lowest row-major pixel index) wins.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/refine_shared.h"

layout(local_size_x = PG_REFINE_THREADS) in;
layout(std430, binding = 0) readonly buffer Labels { uint labels[]; };
layout(std430, binding = 1) readonly buffer Parent { uint parent[]; };
layout(std430, binding = 2) readonly buffer Sizes { uint sizes[]; };
layout(std430, binding = 3) readonly buffer Slots { uint slots[]; };
layout(std430, binding = 4) readonly buffer BestSize { uint best_size[]; };
layout(std430, binding = 5) buffer BestRoot { uint best_root[]; };  // starts at ~0
layout(push_constant) uniform Push { PixelPush pc; };

void main() {
    const uint p = pg_global_index();
    if (p >= pc.width * pc.height) return;
    if (labels[p] == 0u || parent[p] != p) return;
    const uint slot = slots[p];
    if (sizes[p] == best_size[slot]) atomicMin(best_root[slot], p);
}

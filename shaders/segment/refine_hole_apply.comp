#version 450
// Hole filling, step 2 of 2: a 0-component that does not touch the border and whose
// neighbours are all one instance k (lowest == highest == k) becomes k. src may be dst.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/refine_shared.h"

layout(local_size_x = PG_REFINE_THREADS) in;
layout(std430, binding = 0) readonly buffer Src { uint src[]; };
layout(std430, binding = 1) writeonly buffer Dst { uint dst[]; };
layout(std430, binding = 2) readonly buffer Parent { uint parent[]; };
layout(std430, binding = 3) readonly buffer Lowest { uint lowest[]; };
layout(std430, binding = 4) readonly buffer Highest { uint highest[]; };
layout(push_constant) uniform Push { PixelPush pc; };

void main() {
    const uint p = pg_global_index();
    if (p >= pc.width * pc.height) return;
    uint label = src[p];
    if (label == 0u) {
        const uint root = parent[p];
        const uint lo = lowest[root];
        if (lo != 0u && lo == highest[root]) label = lo;
    }
    dst[p] = label;
}

#version 450
// Connected components, step 2 of 3: joins tile-local components across tile borders with
// global union-find. Every pair of adjacent pixels in different tiles has one pixel on the
// top row or left column of its tile, whose W, NW, N, NE and SW neighbours are checked; one
// workgroup per tile, one invocation per such pixel.
#extension GL_GOOGLE_include_directive : require
#include "segment/refine_shared.h"

layout(local_size_x = PG_CC_EDGE_THREADS) in;
layout(std430, binding = 0) readonly buffer Labels { uint labels[]; };
layout(std430, binding = 1) coherent buffer Parent { uint parent[]; };
layout(push_constant) uniform Push { CcPush pc; };
#include "segment/refine_union_find.glsl"

void main() {
    const int t = int(gl_LocalInvocationIndex);
    if (t >= 2 * PG_CC_TILE - 1) return;
    const int tx = int(gl_WorkGroupID.x), ty = int(gl_WorkGroupID.y);
    const int x = tx * PG_CC_TILE + (t < PG_CC_TILE ? t : 0);
    const int y = ty * PG_CC_TILE + (t < PG_CC_TILE ? 0 : t - PG_CC_TILE + 1);
    const int w = int(pc.width), h = int(pc.height);
    if (x >= w || y >= h) return;
    const uint p = uint(y * w + x);
    const uint label = labels[p];
    if (!cc_member(pc.mode, label)) return;
    const ivec2 steps[5] = ivec2[5](ivec2(-1, 0), ivec2(0, -1), ivec2(-1, -1), ivec2(1, -1), ivec2(-1, 1));
    const int n = pc.mode == PG_CC_LABEL_8 ? 5 : 2;
    for (int i = 0; i < n; ++i) {
        const int qx = x + steps[i].x, qy = y + steps[i].y;
        if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
        if (qx / PG_CC_TILE == tx && qy / PG_CC_TILE == ty) continue;  // joined by refine_cc_local
        const uint q = uint(qy * w + qx);
        if (cc_joined(pc.mode, label, labels[q])) uf_union(p, q);
    }
}

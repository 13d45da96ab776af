#version 450
// Connected components, step 3 of 3: every pixel's parent becomes its root, the smallest
// pixel index of its component.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/refine_shared.h"

layout(local_size_x = PG_REFINE_THREADS) in;
layout(std430, binding = 0) coherent buffer Parent { uint parent[]; };
layout(push_constant) uniform Push { CcPush pc; };
#include "segment/refine_union_find.glsl"

void main() {
    const uint p = pg_global_index();
    if (p >= pc.width * pc.height) return;
    const uint up = parent[p];
    if (up == p) return;
    const uint root = uf_find(up);
    if (root != up) parent[p] = root;
}

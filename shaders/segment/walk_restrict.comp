#version 450
// Multigrid, going down: an aggregate's right-hand side is the sum of its nodes' residuals
// r - A z after the pre-smoothing sweep (one thread per aggregate walks its children: no float
// atomics), and the next level's pre-smoothing from 0 is one Jacobi step, z = smoother r.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"

layout(local_size_x = 256) in;
// Reads through texel buffers: gathered in vector code on CPU drivers (walk_apply.comp).
layout(binding = 0, r32ui) readonly uniform uimageBuffer rows;  // this level's operator
layout(binding = 1, r32ui) readonly uniform uimageBuffer columns;
layout(binding = 2, r32f) readonly uniform imageBuffer weights;
layout(binding = 3, r32f) readonly uniform imageBuffer diagonal;
layout(binding = 4, r32ui) readonly uniform uimageBuffer child_rows;  // per aggregate
layout(binding = 5, r32ui) readonly uniform uimageBuffer children;
layout(binding = 6, rgba32f) readonly uniform imageBuffer r;  // this level
layout(binding = 7, rgba32f) readonly uniform imageBuffer pre;
layout(binding = 8, r32f) readonly uniform imageBuffer smoother;  // the next level
layout(std430, binding = 9) writeonly buffer CoarseR { vec4 coarse_r[]; };
layout(std430, binding = 10) writeonly buffer CoarsePre { vec4 coarse_pre[]; };
layout(push_constant) uniform Push { WalkCyclePush pc; };
#ifndef WALK_VECS
#error "WALK_VECS: built per column count (shaders/CMakeLists.txt)"
#endif

void main() {
    uint vecs = WALK_VECS;
    uint a = pg_global_index();
    if (a >= pc.size.y) return;
    vec4 acc[kWalkVecs];
    for (uint c = 0u; c < kWalkVecs; ++c) acc[c] = vec4(0.0);
    const uint last = imageLoad(child_rows, int(a + 1u)).x;
    for (uint t = imageLoad(child_rows, int(a)).x; t < last; ++t) {
        uint i = imageLoad(children, int(t)).x;
        float d = imageLoad(diagonal, int(i)).x;
        for (uint c = 0u; c < vecs; ++c) acc[c] += imageLoad(r, int(i * vecs + c)) - d * imageLoad(pre, int(i * vecs + c));
        const uint end = imageLoad(rows, int(i + 1u)).x;
        for (uint s = imageLoad(rows, int(i)).x; s < end; ++s) {
            uint j = imageLoad(columns, int(s)).x;
            float w = imageLoad(weights, int(s)).x;
            for (uint c = 0u; c < vecs; ++c) acc[c] += w * imageLoad(pre, int(j * vecs + c));
        }
    }
    float m = imageLoad(smoother, int(a)).x;
    for (uint c = 0u; c < vecs; ++c) {
        coarse_r[a * vecs + c] = acc[c];
        coarse_pre[a * vecs + c] = m * acc[c];
    }
}

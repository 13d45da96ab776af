#version 450
// Multigrid, going down: an aggregate's right-hand side is the sum of its nodes' residuals
// r - A z after the pre-smoothing sweep (one thread per aggregate walks its children: no float
// atomics), and the next level's pre-smoothing from 0 is one Jacobi step, z = smoother r.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Rows { uint rows[]; };          // this level's operator
layout(std430, binding = 1) readonly buffer Columns { uint columns[]; };
layout(std430, binding = 2) readonly buffer Weights { float weights[]; };
layout(std430, binding = 3) readonly buffer Diagonal { float diagonal[]; };
layout(std430, binding = 4) readonly buffer ChildRows { uint child_rows[]; };  // per aggregate
layout(std430, binding = 5) readonly buffer Children { uint children[]; };
layout(std430, binding = 6) readonly buffer R { vec4 r[]; };                // this level
layout(std430, binding = 7) readonly buffer Pre { vec4 pre[]; };
layout(std430, binding = 8) readonly buffer Smoother { float smoother[]; }; // the next level
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
    for (uint t = child_rows[a]; t < child_rows[a + 1u]; ++t) {
        uint i = children[t];
        float d = diagonal[i];
        for (uint c = 0u; c < vecs; ++c) acc[c] += r[i * vecs + c] - d * pre[i * vecs + c];
        for (uint s = rows[i]; s < rows[i + 1u]; ++s) {
            uint j = columns[s];
            float w = weights[s];
            for (uint c = 0u; c < vecs; ++c) acc[c] += w * pre[j * vecs + c];
        }
    }
    float m = smoother[a];
    for (uint c = 0u; c < vecs; ++c) {
        coarse_r[a * vecs + c] = acc[c];
        coarse_pre[a * vecs + c] = m * acc[c];
    }
}

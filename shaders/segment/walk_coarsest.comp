#version 450
// Multigrid, the bottom: z = A^+ r on the coarsest level (a few hundred nodes), by the dense
// pseudo-inverse the host computed once per hierarchy: one pass instead of many Jacobi sweeps.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"

layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Inverse { float inverse[]; };  // row-major, nodes^2
layout(std430, binding = 1) readonly buffer R { vec4 r[]; };
layout(std430, binding = 2) writeonly buffer Z { vec4 z[]; };
layout(push_constant) uniform Push { WalkCyclePush pc; };
#ifndef WALK_VECS
#error "WALK_VECS: built per column count (shaders/CMakeLists.txt)"
#endif

void main() {
    uint vecs = WALK_VECS;
    uint i = pg_global_index();
    uint n = pc.size.x;
    if (i >= n) return;
    vec4 acc[kWalkVecs];
    for (uint c = 0u; c < kWalkVecs; ++c) acc[c] = vec4(0.0);
    for (uint j = 0u; j < n; ++j) {
        float m = inverse[i * n + j];
        for (uint c = 0u; c < vecs; ++c) acc[c] += m * r[j * vecs + c];
    }
    for (uint c = 0u; c < vecs; ++c) z[i * vecs + c] = acc[c];
}

#version 450
// y = A v over the unknown nodes, as coupling_i v_i + sum over unknown neighbours w (v_i - v_j)
// (seed rows and columns are out of the system); with mode.x = 1 also the partial dots v . y.
// Not (degree + gamma) v_i - sum w v_j: with few seeds the operator is nearly singular, its
// product is a small difference of two large float sums, and that rounding, new at every
// product, stalls multigrid-preconditioned CG at a relative residual of ~1e-2 and then blows it
// up (the real guitar). The differences v_i - v_j of neighbours are small and exact enough.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Rows { uint rows[]; };
layout(std430, binding = 1) readonly buffer EdgeColumns { uint edge_columns[]; };  // the adjacency's
layout(std430, binding = 2) readonly buffer EdgeWeights { float edge_weights[]; };  // walk_rhs
layout(std430, binding = 3) readonly buffer Coupling { float coupling[]; };  // walk_rhs
layout(std430, binding = 4) readonly buffer Seed { int seed[]; };
layout(std430, binding = 5) readonly buffer V { vec4 v[]; };
layout(std430, binding = 6) writeonly buffer Y { vec4 y[]; };
layout(std430, binding = 7) writeonly buffer Partials { vec4 partials[]; };
layout(push_constant) uniform Push { WalkPush pc; };
#include "segment/walk_common.glsl"

void main() {
    uint vecs = WALK_VECS;
    uint i = pg_global_index();
    uint n = pc.size.x;
    vec4 acc[kWalkVecs], dots[kWalkVecs];
    for (uint c = 0u; c < kWalkVecs; ++c) acc[c] = vec4(0.0), dots[c] = vec4(0.0);
    if (i < n && seed[i] == kWalkFree) {
        vec4 own[kWalkVecs];
        for (uint c = 0u; c < vecs; ++c) own[c] = v[i * vecs + c];
        for (uint s = rows[i]; s < rows[i + 1u]; ++s) {
            uint j = edge_columns[s];
            float w = edge_weights[s];
            for (uint c = 0u; c < vecs; ++c) acc[c] += w * (own[c] - v[j * vecs + c]);
        }
        for (uint c = 0u; c < vecs; ++c) acc[c] += coupling[i] * own[c];
        for (uint c = 0u; c < vecs; ++c) dots[c] = acc[c] * v[i * vecs + c];
    }
    if (i < n)
        for (uint c = 0u; c < vecs; ++c) y[i * vecs + c] = acc[c];
    if (pc.mode.x == 1u) WALK_STORE_PARTIALS(dots, partials);
}

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
// Read through texel buffers: on CPU drivers a texel load is gathered in vector code, a storage
// buffer load at an address that differs between lanes is a loop over the lanes.
layout(binding = 0, r32ui) readonly uniform uimageBuffer rows;
layout(binding = 1, r32ui) readonly uniform uimageBuffer edge_columns;  // the adjacency's
layout(binding = 2, r32f) readonly uniform imageBuffer edge_weights;    // walk_rhs
layout(binding = 3, r32f) readonly uniform imageBuffer coupling;        // walk_rhs
layout(binding = 4, r32i) readonly uniform iimageBuffer seed;
layout(binding = 5, rgba32f) readonly uniform imageBuffer v;
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
    if (i < n && imageLoad(seed, int(i)).x == kWalkFree) {
        vec4 own[kWalkVecs];
        for (uint c = 0u; c < vecs; ++c) own[c] = imageLoad(v, int(i * vecs + c));
        const uint end = imageLoad(rows, int(i + 1u)).x;
        for (uint s = imageLoad(rows, int(i)).x; s < end; ++s) {
            uint j = imageLoad(edge_columns, int(s)).x;
            float w = imageLoad(edge_weights, int(s)).x;
            for (uint c = 0u; c < vecs; ++c) acc[c] += w * (own[c] - imageLoad(v, int(j * vecs + c)));
        }
        const float ci = imageLoad(coupling, int(i)).x;
        for (uint c = 0u; c < vecs; ++c) acc[c] += ci * own[c];
        for (uint c = 0u; c < vecs; ++c) dots[c] = acc[c] * own[c];
    }
    if (i < n)
        for (uint c = 0u; c < vecs; ++c) y[i * vecs + c] = acc[c];
    if (pc.mode.x == 1u) WALK_STORE_PARTIALS(dots, partials);
}

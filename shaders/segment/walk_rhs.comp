#version 450
// The random walker's right-hand side and starting point for the label columns [base, base +
// labels): an unknown node gets b = gamma q + sum over seed neighbours w [seed label];
// a seed holds its label's indicator in x and takes no part in the solve (b = 0, 1/diag = 0).
// The operator's diagonal is degree + gamma; an isolated node without unary stays as it was.
// Also per node its coupling out of the unknowns, gamma + the weights to seeds (walk_apply's
// diagonal excess, summed from the terms themselves rather than as degree - the rest), and its
// row of the walk's edge weights: the adjacency's with every edge into a seed at 0, so walk_apply
// needs no seed test per edge (written here from the seed reads the coupling makes anyway: a
// pass of its own over the edges cost 9-12 ms of a 150 k click).
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"

layout(local_size_x = 256) in;
// Reads through texel buffers: gathered in vector code on CPU drivers (walk_apply.comp).
layout(binding = 0, r32ui) readonly uniform uimageBuffer rows;
layout(binding = 1, r32ui) readonly uniform uimageBuffer columns;
layout(binding = 2, r32f) readonly uniform imageBuffer weights;
layout(binding = 3, r32f) readonly uniform imageBuffer degree;
layout(binding = 4, r32i) readonly uniform iimageBuffer seed;   // label, or kWalkFree
layout(binding = 5, r32f) readonly uniform imageBuffer gamma;   // unary strength
layout(binding = 6, rgba32f) readonly uniform imageBuffer prior;  // WALK_VECS per node
layout(std430, binding = 7) buffer X { vec4 x[]; };                     // start, then solution
layout(std430, binding = 8) writeonly buffer B { vec4 b[]; };
layout(std430, binding = 9) writeonly buffer InvDiag { float inv_diag[]; };
layout(std430, binding = 10) writeonly buffer Coupling { float coupling[]; };
layout(std430, binding = 11) writeonly buffer EdgeWeights { float edge_weights[]; };
layout(push_constant) uniform Push { WalkPush pc; };
#include "segment/walk_common.glsl"

// The indicator of `label` over this solve's columns.
vec4 indicator(int label, uint c) {
    int l = label - int(pc.mode.y) - int(4u * c);
    return vec4(equal(ivec4(l), ivec4(0, 1, 2, 3)));
}

void main() {
    uint vecs = WALK_VECS;
    uint i = pg_global_index();
    uint n = pc.size.x;
    if (i >= n) return;
    int own = imageLoad(seed, int(i)).x;
    const uint first = imageLoad(rows, int(i)).x, end = imageLoad(rows, int(i + 1u)).x;
    if (own != kWalkFree) {
        for (uint s = first; s < end; ++s)
            edge_weights[s] = imageLoad(seed, int(imageLoad(columns, int(s)).x)).x == kWalkFree ? imageLoad(weights, int(s)).x : 0.0;
        for (uint c = 0u; c < vecs; ++c) {
            x[i * vecs + c] = indicator(own, c);
            b[i * vecs + c] = vec4(0.0);
        }
        inv_diag[i] = 0.0;
        coupling[i] = 0.0;
        return;
    }
    vec4 acc[kWalkVecs];
    const float g = imageLoad(gamma, int(i)).x;
    for (uint c = 0u; c < vecs; ++c) acc[c] = g * imageLoad(prior, int(i * vecs + c));
    float couple = g;
    for (uint s = first; s < end; ++s) {
        int other = imageLoad(seed, int(imageLoad(columns, int(s)).x)).x;
        float w = imageLoad(weights, int(s)).x;
        edge_weights[s] = other == kWalkFree ? w : 0.0;
        if (other == kWalkFree) continue;
        couple += w;
        for (uint c = 0u; c < vecs; ++c) acc[c] += w * indicator(other, c);
    }
    for (uint c = 0u; c < vecs; ++c) b[i * vecs + c] = acc[c];
    float diag = imageLoad(degree, int(i)).x + g;
    inv_diag[i] = diag > 0.0 ? 1.0 / diag : 0.0;
    coupling[i] = couple;
}

#version 450
// The adjacency's reverse half: kNN slot t (node i = t / k lists j = nbr[t]) is also an entry of
// row j unless j lists i too; then the pair is j's own entry of row j (and i's of row i), and
// the slot's twin, j's slot that lists i, is kept for the weights. Each row counts the slots
// it receives this way (graph_reverse then places them).
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"

layout(local_size_x = 256) in;
// Reads through texel buffers: gathered in vector code on CPU drivers (graph_knn.comp).
layout(binding = 0, r32ui) readonly uniform uimageBuffer nbr;
layout(std430, binding = 1) writeonly buffer Twin { uint twin[]; };  // kGraphNone: none
layout(std430, binding = 2) buffer ReverseCount { uint reverse_count[]; };  // zeroed
layout(push_constant) uniform Push { GraphEdgesPush pc; };

void main() {
    uint t = pg_global_index();
    uint n = pc.size.x, k = pc.size.y;
    if (t >= n * k) return;
    uint i = t / k, j = imageLoad(nbr, int(t)).x, other = kGraphNone;
    if (j == kGraphNone) {
        twin[t] = kGraphNone;
        return;
    }
    for (uint u = 0u; u < k; ++u)
        if (imageLoad(nbr, int(j * k + u)).x == i) other = j * k + u;
    twin[t] = other;
    if (other == kGraphNone) atomicAdd(reverse_count[j], 1u);
}

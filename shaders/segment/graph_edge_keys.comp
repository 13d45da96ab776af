#version 450
// Keys for the adjacency's reverse half: kNN slot t (node i = t / k lists j = nbr[t]) is also an
// entry of row j, with id n*k + t, unless j lists i too: then the pair is j's own entry of row j
// (and i's of row i), and the slot's twin, j's slot that lists i, is kept for the weights.
// Empty and twinned slots get key n (sorted last). A row's own entries need no sort: they are
// its filled slots, in order.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Nbr { uint nbr[]; };
layout(std430, binding = 1) writeonly buffer Keys { uint keys[]; };
layout(std430, binding = 2) writeonly buffer Values { uint values[]; };
layout(std430, binding = 3) writeonly buffer Twin { uint twin[]; };  // kGraphNone: none
layout(push_constant) uniform Push { GraphEdgesPush pc; };

void main() {
    uint t = pg_global_index();
    uint n = pc.size.x, k = pc.size.y, half_ = n * k;
    if (t >= half_) return;
    uint i = t / k, j = nbr[t], other = kGraphNone;
    if (j != kGraphNone)
        for (uint u = 0u; u < k; ++u)
            if (nbr[j * k + u] == i) other = j * k + u;
    twin[t] = other;
    keys[t] = j == kGraphNone || other != kGraphNone ? n : j;
    values[t] = half_ + t;
}

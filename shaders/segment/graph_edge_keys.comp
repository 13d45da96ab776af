#version 450
// Keys for the symmetric adjacency: entry e < n*k is kNN slot e under its row i, entry
// n*k + e is the same edge reversed, under row j. Empty slots get key n (sorted last).
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Nbr { uint nbr[]; };
layout(std430, binding = 1) writeonly buffer Keys { uint keys[]; };
layout(std430, binding = 2) writeonly buffer Values { uint values[]; };
layout(push_constant) uniform Push { GraphEdgesPush pc; };

void main() {
    uint e = pg_global_index();
    uint n = pc.size.x, k = pc.size.y, half_ = n * k;
    if (e >= pc.size.z) return;
    uint slot = e < half_ ? e : e - half_;
    uint j = nbr[slot];
    keys[e] = j == kGraphNone ? n : (e < half_ ? slot / k : j);
    values[e] = e;
}

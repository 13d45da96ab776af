#version 450
// Row i of W + W^T, each pair once: its own filled slots in order (a pair that lists each other
// weighs both slots, summed the same way in both rows, so the matrix stays exactly symmetric),
// then the slots of nodes that list i and that i does not list, in slot id order (graph_reverse
// left them in the row's tail in any order; an insertion sort, as a row receives a few); and the
// node's degree, summed in row order.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"

layout(local_size_x = 256) in;
// Reads through texel buffers: gathered in vector code on CPU drivers (graph_knn.comp).
layout(binding = 0, r32ui) readonly uniform uimageBuffer nbr;
layout(binding = 1, r32ui) readonly uniform uimageBuffer twin;
layout(binding = 2, r32f) readonly uniform imageBuffer weight;  // per kNN slot
layout(binding = 3, r32ui) readonly uniform uimageBuffer rows;
layout(std430, binding = 4) buffer Columns { uint columns[]; };  // the tails' slot ids in, columns out
layout(std430, binding = 5) writeonly buffer Weights { float weights[]; };
layout(std430, binding = 6) writeonly buffer Degree { float degree[]; };
layout(push_constant) uniform Push { GraphEdgesPush pc; };

void main() {
    uint i = pg_global_index();
    uint n = pc.size.x, k = pc.size.y;
    if (i >= n) return;
    uint s = imageLoad(rows, int(i)).x, end = imageLoad(rows, int(i + 1u)).x;
    uint own = 0u;
    for (uint t = i * k; t < i * k + k; ++t) own += imageLoad(nbr, int(t)).x != kGraphNone ? 1u : 0u;
    uint tail = s + own;
    for (uint a = tail + 1u; a < end; ++a) {
        uint v = columns[a], b = a;
        for (; b > tail && columns[b - 1u] > v; --b) columns[b] = columns[b - 1u];
        columns[b] = v;
    }
    float d = 0.0;
    for (uint t = i * k; t < i * k + k; ++t) {
        uint j = imageLoad(nbr, int(t)).x;
        if (j == kGraphNone) continue;
        // i's weight + j's here, j's + i's in row j: float addition commutes exactly.
        uint other = imageLoad(twin, int(t)).x;
        float wt = imageLoad(weight, int(t)).x;
        float w = other == kGraphNone ? wt : wt + imageLoad(weight, int(other)).x;
        columns[s] = j;
        weights[s] = w;
        d += w;
        ++s;
    }
    for (; s < end; ++s) {
        uint slot = columns[s];
        columns[s] = slot / k;
        const float ws = imageLoad(weight, int(slot)).x;
        weights[s] = ws;
        d += ws;
    }
    degree[i] = d;
}

#version 450
// Row i of W + W^T, each pair once: its own filled slots in order (a pair that lists each other
// weighs both slots, summed the same way in both rows, so the matrix stays exactly symmetric),
// then the slots of nodes that list i and that i does not list, in id order (the stable sort's
// run); and the node's degree, summed in row order.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Nbr { uint nbr[]; };
layout(std430, binding = 1) readonly buffer Values { uint values[]; };  // sorted reverse ids
layout(std430, binding = 2) readonly buffer ReverseStart { uint reverse_start[]; };
layout(std430, binding = 3) readonly buffer Twin { uint twin[]; };
layout(std430, binding = 4) readonly buffer Weight { float weight[]; };  // per kNN slot
layout(std430, binding = 5) readonly buffer Rows { uint rows[]; };
layout(std430, binding = 6) writeonly buffer Columns { uint columns[]; };
layout(std430, binding = 7) writeonly buffer Weights { float weights[]; };
layout(std430, binding = 8) writeonly buffer Degree { float degree[]; };
layout(push_constant) uniform Push { GraphEdgesPush pc; };

void main() {
    uint i = pg_global_index();
    uint n = pc.size.x, k = pc.size.y, half_ = n * k;
    if (i >= n) return;
    uint s = rows[i], end = rows[i + 1u];
    float d = 0.0;
    for (uint t = i * k; t < i * k + k; ++t) {
        uint j = nbr[t];
        if (j == kGraphNone) continue;
        // i's weight + j's here, j's + i's in row j: float addition commutes exactly.
        uint other = twin[t];
        float w = other == kGraphNone ? weight[t] : weight[t] + weight[other];
        columns[s] = j;
        weights[s] = w;
        d += w;
        ++s;
    }
    for (uint r = reverse_start[i]; s < end; ++r, ++s) {
        uint slot = values[r] - half_;
        columns[s] = slot / k;
        weights[s] = weight[slot];
        d += weight[slot];
    }
    degree[i] = d;
}

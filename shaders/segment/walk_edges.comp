#version 450
// The solve's adjacency in the order walk_apply reads it: per entry of the symmetric rows, the
// other node and the weight, 0 where that node is a seed (seeds are out of the system and enter
// through the right-hand side). Saves walk_apply three dependent loads per entry.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"
#include "segment/graph_edge.glsl"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Values { uint values[]; };
layout(std430, binding = 1) readonly buffer Nbr { uint nbr[]; };
layout(std430, binding = 2) readonly buffer Weight { float weight[]; };
layout(std430, binding = 3) readonly buffer Seed { int seed[]; };
layout(std430, binding = 4) readonly buffer Rows { uint rows[]; };
// Two arrays, not one of pairs: each stays under the binding limit for twice the nodes.
layout(std430, binding = 5) writeonly buffer EdgeColumns { uint edge_columns[]; };
layout(std430, binding = 6) writeonly buffer EdgeWeights { float edge_weights[]; };
layout(push_constant) uniform Push { WalkPush pc; };

void main() {
    uint s = pg_global_index();
    uint n = pc.size.x, k = pc.size.y, half_ = n * k;
    if (s >= rows[n]) return;
    uint e = values[s];
    uint j = EDGE_COLUMN(e, half_, k);
    edge_columns[s] = j;
    edge_weights[s] = seed[j] == kWalkFree ? weight[edge_slot(e, half_)] : 0.0;
}

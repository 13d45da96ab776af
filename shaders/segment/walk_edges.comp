#version 450
// The walk's copy of the adjacency's weights with every edge into a seed at 0: walk_apply then
// needs no seed test per edge (a seed's value enters through the right-hand side).
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Columns { uint columns[]; };
layout(std430, binding = 1) readonly buffer Weights { float weights[]; };
layout(std430, binding = 2) readonly buffer Seed { int seed[]; };
layout(std430, binding = 3) readonly buffer Rows { uint rows[]; };
layout(std430, binding = 4) writeonly buffer EdgeWeights { float edge_weights[]; };
layout(push_constant) uniform Push { WalkPush pc; };

void main() {
    uint s = pg_global_index();
    if (s >= rows[pc.size.x]) return;
    edge_weights[s] = seed[columns[s]] == kWalkFree ? weights[s] : 0.0;
}

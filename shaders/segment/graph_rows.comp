#version 450
// Row starts of the sorted adjacency (rows[n] = entries in use) and each node's degree.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"
#include "segment/graph_edge.glsl"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Keys { uint keys[]; };  // sorted rows
layout(std430, binding = 1) readonly buffer Values { uint values[]; };
layout(std430, binding = 2) readonly buffer Nbr { uint nbr[]; };
layout(std430, binding = 3) readonly buffer Weight { float weight[]; };
layout(std430, binding = 4) writeonly buffer Rows { uint rows[]; };
layout(std430, binding = 5) writeonly buffer Degree { float degree[]; };
layout(push_constant) uniform Push { GraphEdgesPush pc; };

uint lower_bound(uint key) {
    uint lo = 0u, hi = pc.size.z;
    while (lo < hi) {
        uint mid = (lo + hi) >> 1;
        if (keys[mid] < key) lo = mid + 1u; else hi = mid;
    }
    return lo;
}

void main() {
    uint i = pg_global_index();
    uint n = pc.size.x;
    if (i > n) return;
    uint start = lower_bound(i);
    rows[i] = start;
    if (i == n) return;
    float d = 0.0;
    for (uint s = start; s < pc.size.z && keys[s] == i; ++s) d += weight[edge_slot(values[s], n * pc.size.y)];
    degree[i] = d;
}

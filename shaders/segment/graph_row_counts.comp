#version 450
// Each node's row length in W + W^T with each pair once: its filled kNN slots plus the slots of
// nodes that list it and that it does not list (graph_twins' count); a prefix sum turns the
// lengths into row starts.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Nbr { uint nbr[]; };
layout(std430, binding = 1) readonly buffer ReverseCount { uint reverse_count[]; };
layout(std430, binding = 2) writeonly buffer Counts { uint counts[]; };
layout(push_constant) uniform Push { GraphEdgesPush pc; };

void main() {
    uint i = pg_global_index();
    uint n = pc.size.x, k = pc.size.y;
    if (i > n) return;
    if (i == n) {  // the scan's extra slot: rows[n] becomes the entry count
        counts[n] = 0u;
        return;
    }
    uint own = 0u;
    for (uint t = 0u; t < k; ++t) own += nbr[i * k + t] != kGraphNone ? 1u : 0u;
    counts[i] = own + reverse_count[i];
}

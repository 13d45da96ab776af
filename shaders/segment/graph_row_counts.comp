#version 450
// Each node's row length in W + W^T with each pair once: its filled kNN slots plus the slots of
// nodes that list it and that it does not list (a run of the sorted reverse keys, whose start is
// kept); a prefix sum turns the lengths into row starts.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Nbr { uint nbr[]; };
layout(std430, binding = 1) readonly buffer Keys { uint keys[]; };  // sorted, n k of them
layout(std430, binding = 2) writeonly buffer Counts { uint counts[]; };
layout(std430, binding = 3) writeonly buffer ReverseStart { uint reverse_start[]; };
layout(push_constant) uniform Push { GraphEdgesPush pc; };

uint lower_bound(uint key, uint count) {
    uint lo = 0u, hi = count;
    while (lo < hi) {
        uint mid = (lo + hi) >> 1;
        if (keys[mid] < key) lo = mid + 1u; else hi = mid;
    }
    return lo;
}

void main() {
    uint i = pg_global_index();
    uint n = pc.size.x, k = pc.size.y, half_ = n * k;
    if (i > n) return;
    if (i == n) {  // the scan's extra slot: rows[n] becomes the entry count
        counts[n] = 0u;
        return;
    }
    uint own = 0u;
    for (uint t = 0u; t < k; ++t) own += nbr[i * k + t] != kGraphNone ? 1u : 0u;
    uint first = lower_bound(i, half_);
    counts[i] = own + lower_bound(i + 1u, half_) - first;
    reverse_start[i] = first;
}

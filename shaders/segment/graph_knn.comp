#version 450
// k nearest neighbours of every node among the nodes of its own and the 26 surrounding grid
// cells (exact within one cell side), nearest first, and the node's local spacing (the mean
// distance to them). A node with fewer than k there may search further shells of cells (dims.w,
// at most kGraphMaxShells): sparse Gaussians (large ones, floaters, thin parts) are otherwise
// islands no seed reaches. A cell's nodes are found by a binary search in the sorted cell keys.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"
#include "segment/graph_grid.glsl"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Pos { vec4 pos[]; };
layout(std430, binding = 1) readonly buffer Keys { uint keys[]; };      // sorted
layout(std430, binding = 2) readonly buffer Values { uint values[]; };  // node of each sorted key
layout(std430, binding = 3) writeonly buffer Nbr { uint nbr[]; };       // k per node, kGraphNone if fewer
layout(std430, binding = 4) writeonly buffer Dist { float dist[]; };    // k per node
layout(std430, binding = 5) writeonly buffer Spacing { float spacing[]; };
layout(push_constant) uniform Push { GraphGridPush pc; };

uint lower_bound(uint key, uint n) {
    uint lo = 0u, hi = n;
    while (lo < hi) {
        uint mid = (lo + hi) >> 1;
        if (keys[mid] < key) lo = mid + 1u; else hi = mid;
    }
    return lo;
}

void main() {
    uint i = pg_global_index();
    uint n = pc.bits.z, k = pc.bits.w;
    if (i >= n) return;
    vec3 p = pos[i].xyz;
    ivec3 c = cell_of(p, pc.origin, pc.dims);
    float best_d[kGraphMaxK];
    uint best_j[kGraphMaxK];
    for (uint t = 0u; t < kGraphMaxK; ++t) best_d[t] = 3.4e38, best_j[t] = kGraphNone;
    uint found = 0u;
    int shells = int(min(max(pc.dims.w, 1u), kGraphMaxShells));
    for (int ring = 0; ring <= shells && (ring <= 1 || found < k); ++ring)
        for (int dz = -ring; dz <= ring; ++dz)
            for (int dy = -ring; dy <= ring; ++dy)
                for (int dx = -ring; dx <= ring; ++dx) {
                    // Ring 0 is the node's cell, ring r the shell of cells r steps away.
                    if (max(abs(dx), max(abs(dy), abs(dz))) != ring) continue;
                    ivec3 q = c + ivec3(dx, dy, dz);
                    if (any(lessThan(q, ivec3(0))) || any(greaterThanEqual(q, ivec3(pc.dims.xyz)))) continue;
                    uint key = cell_key(q, pc.bits);
                    for (uint s = lower_bound(key, n); s < n && keys[s] == key; ++s) {
                        uint j = values[s];
                        if (j == i) continue;
                        vec3 d = pos[j].xyz - p;
                        float d2 = dot(d, d);
                        // Ties go to the smaller node id, so the result does not depend on the scan order.
                        uint last = k - 1u;
                        if (d2 > best_d[last] || (d2 == best_d[last] && j >= best_j[last])) continue;
                        uint t = last;
                        while (t > 0u && (d2 < best_d[t - 1u] || (d2 == best_d[t - 1u] && j < best_j[t - 1u]))) {
                            best_d[t] = best_d[t - 1u];
                            best_j[t] = best_j[t - 1u];
                            --t;
                        }
                        best_d[t] = d2;
                        best_j[t] = j;
                        found = min(found + 1u, k);
                    }
                }
    float sum = 0.0;
    for (uint t = 0u; t < k; ++t) {
        bool ok = t < found;
        nbr[i * k + t] = ok ? best_j[t] : kGraphNone;
        float d = ok ? sqrt(best_d[t]) : 0.0;
        dist[i * k + t] = d;
        sum += d;
    }
    spacing[i] = found > 0u ? sum / float(found) : 0.0;
}

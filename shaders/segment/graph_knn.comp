#version 450
// k nearest neighbours of every node among the nodes of its own and the 26 surrounding grid
// cells (exact within one cell side), nearest first, and the node's local spacing (the mean
// distance to them). A node with fewer than k there may search further shells of cells (dims.w,
// at most kGraphMaxShells): sparse Gaussians (large ones, floaters, thin parts) are otherwise
// islands no seed reaches. A row of cells' nodes are found by a binary search in the sorted cell keys.
// Past kGraphMaxScan candidates a node keeps the nearest it has found: a cell that holds a large
// share of the scene (thousands of Gaussians collapsed onto one point) would otherwise make the
// search quadratic. Real and synthetic scenes scan at most ~300 (median 18-43).
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
    uint found = 0u, scanned = 0u;
    int shells = int(min(max(pc.dims.w, 1u), kGraphMaxShells));
    for (int ring = 0; ring <= shells && (ring <= 1 || found < k); ++ring)
        for (int dz = -ring; dz <= ring; ++dz)
            for (int dy = -ring; dy <= ring; ++dy) {
                // Ring 0 is the node's cell, ring r the shell of cells r steps away. Cells adjacent
                // in x have consecutive keys, so a row of the shell is one run of the sorted keys
                // (one binary search, not one per cell); a row inside the shell holds two cells.
                ivec2 q = c.yz + ivec2(dy, dz);
                if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, ivec2(pc.dims.yz)))) continue;
                bool whole = max(abs(dy), abs(dz)) == ring;
                for (int part = 0; part < (whole ? 1 : 2); ++part) {
                    int x0 = whole || part == 0 ? c.x - ring : c.x + ring;
                    int x1 = whole || part == 1 ? c.x + ring : c.x - ring;
                    x0 = max(x0, 0);
                    x1 = min(x1, int(pc.dims.x) - 1);
                    if (x0 > x1) continue;
                    uint first = cell_key(ivec3(x0, q), pc.bits), last = cell_key(ivec3(x1, q), pc.bits);
                    for (uint s = lower_bound(first, n); s < n && keys[s] <= last && scanned < kGraphMaxScan; ++s, ++scanned) {
                        uint j = values[s];
                        if (j == i) continue;
                        vec3 d = pos[j].xyz - p;
                        float d2 = dot(d, d);
                        // Ties go to the smaller node id, so the result does not depend on the scan order.
                        uint tail = k - 1u;
                        if (d2 > best_d[tail] || (d2 == best_d[tail] && j >= best_j[tail])) continue;
                        uint t = tail;
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

#version 450
// k nearest neighbours of every node among the nodes of its own and the 26 surrounding grid
// cells (exact within one cell side), nearest first, and the node's local spacing (the mean
// distance to them). A node with fewer than k there may search further shells of cells (dims.w,
// at most kGraphMaxShells): sparse Gaussians (large ones, floaters, thin parts) are otherwise
// islands no seed reaches. A row of cells' nodes are one run of the sorted keys, found by a
// binary search inside the run of their whole row of cells along x (row_start).
// Past kGraphMaxScan candidates a node keeps the nearest it has found: a cell that holds a large
// share of the scene (thousands of Gaussians collapsed onto one point) would otherwise make the
// search quadratic. Real and synthetic scenes scan at most ~300 (median 18-43).
// Invocations take the nodes in sorted order, so a SIMD group's lanes share cells: their loops
// run about as long and their loads hit the same lines. The further shells run as a second pass
// (pass.x 1) over the few nodes the first (pass.x 0) listed as short of k: in one pass a SIMD
// group waits on its sparsest lane's shells (the 150 k guitar's search: 106 ms in one pass).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"
#include "segment/graph_grid.glsl"

layout(local_size_x = 256) in;
// Reads through texel buffers: on CPU drivers a texel load is gathered in vector code, a storage
// buffer load at an address that differs between lanes is a loop over the lanes.
layout(binding = 0, rgba32ui) readonly uniform uimageBuffer sorted_pos;  // graph_sorted
layout(binding = 1, r32ui) readonly uniform uimageBuffer keys;           // sorted
layout(binding = 2, r32ui) readonly uniform uimageBuffer row_start;      // graph_cells, scanned
layout(std430, binding = 3) writeonly buffer Nbr { uint nbr[]; };       // k per node, kGraphNone if fewer
layout(std430, binding = 4) writeonly buffer Dist { float dist[]; };    // k per node
layout(std430, binding = 5) writeonly buffer Spacing { float spacing[]; };
// [0..2] the second pass's dispatch (x: groups), [3] how many are listed, then their sorted indices.
layout(std430, binding = 6) buffer Short { uint short_list[]; };
layout(push_constant) uniform Push { GraphGridPush pc; };
// The lists' length, built per bound on k (shaders/CMakeLists.txt): every list entry costs each
// insertion a compare-and-swap, so lists longer than k cost time for nothing (at k 10, lists of
// 16 took the 150 k guitar's search 35 % longer).
#ifndef GRAPH_K
#error "GRAPH_K: built per bound on k (shaders/CMakeLists.txt)"
#endif
const uint KNN_K = GRAPH_K;

uint lower_bound(uint key, uint lo, uint hi) {
    while (lo < hi) {
        uint mid = (lo + hi) >> 1;
        if (imageLoad(keys, int(mid)).x < key) lo = mid + 1u; else hi = mid;
    }
    return lo;
}

void main() {
    uint n = pc.bits.z, k = pc.bits.w;
    uint g;
    if (pc.pass.x == 0u) {
        g = pg_global_index();
        if (g >= n) return;
    } else {
        uint t = gl_GlobalInvocationID.x;
        if (t >= short_list[3]) return;
        g = short_list[4u + t];
    }
    uvec4 own = imageLoad(sorted_pos, int(g));
    uint i = own.w;
    vec3 p = uintBitsToFloat(own.xyz);
    ivec3 c = cell_of(p, pc.origin, pc.dims);
    float best_d[KNN_K];
    uint best_j[KNN_K];
    [[unroll]] for (uint t = 0u; t < KNN_K; ++t) best_d[t] = 3.4e38, best_j[t] = kGraphNone;
    float worst_d = 3.4e38;  // the k-th nearest so far
    uint worst_j = kGraphNone;
    uint found = 0u, scanned = 0u;
    int shells = int(min(max(pc.dims.w, 1u), kGraphMaxShells));
    int last = pc.pass.x == 0u ? 1 : shells;
    for (int ring = 0; ring <= last && (ring <= 1 || found < k); ++ring)
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
                    uint row = uint(q.x) + pc.dims.y * uint(q.y), end = imageLoad(row_start, int(row + 1u)).x;
                    for (uint s = lower_bound(first, imageLoad(row_start, int(row)).x, end);
                         s < end && imageLoad(keys, int(s)).x <= last && scanned < kGraphMaxScan; ++s, ++scanned) {
                        uvec4 other = imageLoad(sorted_pos, int(s));
                        uint j = other.w;
                        if (j == i) continue;
                        vec3 d = uintBitsToFloat(other.xyz) - p;
                        float d2 = dot(d, d);
                        // Ties go to the smaller node id, so the result does not depend on the scan order.
                        if (d2 > worst_d || (d2 == worst_d && j >= worst_j)) continue;
                        // Into the sorted list by compare-and-swap at constant indices: the lists stay
                        // in registers (an index that varies is memory, lane by lane, on lavapipe).
                        float cd = d2;
                        uint cj = j;
                        [[unroll]] for (uint t = 0u; t < KNN_K; ++t) {
                            bool before = cd < best_d[t] || (cd == best_d[t] && cj < best_j[t]);
                            float td = best_d[t];
                            uint tj = best_j[t];
                            best_d[t] = before ? cd : td;
                            best_j[t] = before ? cj : tj;
                            cd = before ? td : cd;
                            cj = before ? tj : cj;
                        }
                        [[unroll]] for (uint t = 0u; t < KNN_K; ++t)
                            if (t + 1u == k) worst_d = best_d[t], worst_j = best_j[t];
                        found = min(found + 1u, k);
                    }
                }
            }
    if (pc.pass.x == 0u && found < k && shells > 1) {
        uint slot = atomicAdd(short_list[3], 1u);
        short_list[4u + slot] = g;
        if (slot % gl_WorkGroupSize.x == 0u) atomicAdd(short_list[0], 1u);
        return;
    }
    float sum = 0.0;
    [[unroll]] for (uint t = 0u; t < KNN_K; ++t) {
        if (t >= k) break;
        bool ok = t < found;
        nbr[i * k + t] = ok ? best_j[t] : kGraphNone;
        float d = ok ? sqrt(best_d[t]) : 0.0;
        dist[i * k + t] = d;
        sum += d;
    }
    spacing[i] = found > 0u ? sum / float(found) : 0.0;
}

// k-means assignment, one block of centroids: every point of a window compares itself with
// centroids first .. first + BLOCK - 1 and keeps the nearest so far (squared distance in
// `best`, index in `labels`; the host fills them with +inf and 0 before the first block).
// Ties go to the lower index: blocks run in ascending order and only a strictly smaller
// distance replaces the best. Centroids past the last one repeat it, and never win.
//
// The block passes through shared memory; everything else is unrolled, without loops or
// branches around the loads (kmeans_shared.h says why), so on lavapipe every centroid value is
// one broadcast load that serves the ROWS points of each SIMD lane. Lanes past the window
// repeat its last point and store nothing.
// The including shader defines DIMS (floats per point), BLOCK (centroids per dispatch) and
// ROWS (points per invocation).
#extension GL_EXT_control_flow_attributes : require
#include "common/dispatch.glsl"
#include "compress/kmeans_shared.h"

layout(local_size_x = PG_KMEANS_THREADS) in;
layout(std430, binding = 0) readonly buffer Points { float points[]; };  // the window's points
layout(std430, binding = 1) readonly buffer Centroids { float centroids[]; };
layout(std430, binding = 2) buffer Best { float best[]; };    // the window's slice
layout(std430, binding = 3) buffer Labels { uint labels[]; };  // the window's slice
layout(push_constant) uniform Push { KmeansAssignPush pc; };

#define TILE_LOADS ((BLOCK * DIMS + PG_KMEANS_THREADS - 1) / PG_KMEANS_THREADS)
shared float tile[TILE_LOADS * PG_KMEANS_THREADS];

void main() {
    const uint lane = gl_LocalInvocationIndex;
    [[unroll]] for (uint j = 0u; j < TILE_LOADS; ++j) {
        const uint t = j * PG_KMEANS_THREADS + lane;
        tile[t] = centroids[min(pc.first + t / DIMS, pc.last) * DIMS + t % DIMS];
    }
    const uint base = pg_group_index() * (PG_KMEANS_THREADS * ROWS) + lane;
    float p[ROWS * DIMS], nearest[ROWS];
    uint label[ROWS];
    [[unroll]] for (uint r = 0u; r < ROWS; ++r) {
        const uint row = min(base + r * PG_KMEANS_THREADS, pc.n - 1u);
        [[unroll]] for (uint d = 0u; d < DIMS; ++d) p[r * DIMS + d] = points[row * DIMS + d];
        nearest[r] = best[row];
        label[r] = labels[row];
    }
    barrier();
    [[unroll]] for (uint c = 0u; c < BLOCK; ++c) {
        float d2[ROWS];
        [[unroll]] for (uint r = 0u; r < ROWS; ++r) d2[r] = 0.0;
        [[unroll]] for (uint d = 0u; d < DIMS; ++d) {
            const float x = tile[c * DIMS + d];
            [[unroll]] for (uint r = 0u; r < ROWS; ++r) {
                const float e = p[r * DIMS + d] - x;
                d2[r] += e * e;
            }
        }
        const uint at = min(pc.first + c, pc.last);
        [[unroll]] for (uint r = 0u; r < ROWS; ++r) {
            const bool closer = d2[r] < nearest[r];
            nearest[r] = closer ? d2[r] : nearest[r];
            label[r] = closer ? at : label[r];
        }
    }
    [[unroll]] for (uint r = 0u; r < ROWS; ++r) {
        const uint i = base + r * PG_KMEANS_THREADS;
        if (i < pc.n) {
            best[i] = nearest[r];
            labels[i] = label[r];
        }
    }
}

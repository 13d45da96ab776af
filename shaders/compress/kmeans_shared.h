// Layouts and constants shared by engine/compress/kmeans (C++) and the shaders/compress/kmeans_*
// kernels (GLSL): one definition, no drift.
//
// Written around two facts of lavapipe (llvmpipe), where k-means runs in tests and for users:
// - a memory access inside a loop or branch is a scalar loop over the SIMD lanes, even when
//   every lane reads the same address; a top-level access at an address made of constants and
//   push constants is one broadcast load, cheapest from shared memory (storage buffer loads are
//   bounds-checked one by one);
// - a shader's loops together end after 65535 iterations, silently.
// So the assignment has no loops: a dispatch stages a block of centroids in shared memory and
// compares every point with all of them, unrolled, keeping the best so far in a buffer; and the
// loops that follow the data (a cluster's members) are cut into pieces of bounded length.
#ifndef PG_KMEANS_SHARED_H
#define PG_KMEANS_SHARED_H

#ifdef __cplusplus
#include <cstdint>
namespace pg::compress::gpu {
using uint = uint32_t;
#endif

#define PG_KMEANS_THREADS 64
// Point widths with an assignment kernel (kmeans_assign_dD); other widths are padded with zero
// coordinates up to the next one, which changes no distance.
#define PG_KMEANS_MAX_DIMS 45
// kmeans_assign_dD: centroids per dispatch (a shared-memory block) and points per invocation
// (each broadcast centroid value serves them all). Tuned on lavapipe: past these, larger blocks
// and more points only cost compile time and registers (45 floats spill either way).
#define PG_KMEANS_BLOCK_D1 256
#define PG_KMEANS_ROWS_D1 2
#define PG_KMEANS_BLOCK_D3 128
#define PG_KMEANS_ROWS_D3 4
#define PG_KMEANS_BLOCK_D9 128
#define PG_KMEANS_ROWS_D9 4
#define PG_KMEANS_BLOCK_D24 64
#define PG_KMEANS_ROWS_D24 2
#define PG_KMEANS_BLOCK_D45 32
#define PG_KMEANS_ROWS_D45 4
// Sorted members one kmeans_piece_sums invocation walks (a chunk). Windows of at most
// 2^25 points keep the chunks a cluster spans, kmeans_accumulate's loop, under 65535.
#define PG_KMEANS_CHUNK 1024

// kmeans_assign_dD: points [0, n) of a window against centroids first .. first + block - 1
// (clamped to last = k - 1: a repeated centroid never wins, ties go to the lower index).
struct KmeansAssignPush {
    uint n, first, last, pad;
};
// kmeans_bounds: the n sorted labels of a window.
struct KmeansBoundsPush {
    uint n, pad0, pad1, pad2;
};
// kmeans_piece_sums: n sorted members of a window, `chunks` chunks of them, dims floats each.
struct KmeansPiecePush {
    uint n, dims, chunks, pad;
};
// kmeans_accumulate, kmeans_update: k centroids of dims floats.
struct KmeansClusterPush {
    uint k, dims, pad0, pad1;
};

#ifdef __cplusplus
}  // namespace pg::compress::gpu
#endif
#endif

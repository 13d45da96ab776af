// Layouts and constants shared by engine/segment/mask_refine (C++) and the
// shaders/segment/refine_* kernels (GLSL): one definition, no drift.
#ifndef PG_REFINE_SHARED_H
#define PG_REFINE_SHARED_H

#ifdef __cplusplus
#include <cstdint>
namespace pg::seg::gpu {
using uint = uint32_t;
#endif

// Closing (refine_close, refine_close_global): one workgroup closes one square output tile of
// side T, reading the tile plus a 2r apron (the region, side E = T + 4r). The instances within
// r of the tile are taken in ascending batches.
#define PG_CLOSE_THREADS 256
// refine_close: the region lies in a 64 x 64 grid, a region row is 64 bits (one uvec2) per
// instance, in shared memory, for batches of PG_CLOSE_BATCH instances. Used while
// T = 64 - 4r >= PG_CLOSE_MIN_TILE.
#define PG_CLOSE_REGION 64
#define PG_CLOSE_BATCH 16
#define PG_CLOSE_MIN_TILE 16
// refine_close_global (larger radii): a uint of instance bits per region pixel, batches of
// 32, in a global scratch slice per workgroup; T = max(PG_CLOSE_GLOBAL_TILE, 4r); loops
// stride over the region as 16 x 16.
#define PG_CLOSE_GLOBAL_BATCH 32
#define PG_CLOSE_GLOBAL_TILE 32
#define PG_CLOSE_SIDE 16

// Connected components (refine_cc_*): union-find, first inside 32x32 tiles in shared memory
// (4 pixels per invocation: fewer workgroups and barriers), then across tile borders in global
// memory. The root of a component is its smallest row-major pixel index.
#define PG_CC_TILE 32
#define PG_CC_THREADS 256
#define PG_CC_PIXELS (PG_CC_TILE * PG_CC_TILE / PG_CC_THREADS)  // 4 per invocation
#define PG_CC_EDGE_THREADS 64  // one tile's top row and left column (63 pixels)
// What joins two pixels (CcPush.mode).
#define PG_CC_ZERO_4 0    // both 0, 4-connected (holes)
#define PG_CC_LABEL_8 1   // same non-zero label, 8-connected (instance components)

// Elementwise passes over pixels.
#define PG_REFINE_THREADS 256

// refine_close, refine_close_global.
struct ClosePush {
    uint width, height;
    uint radius;
    uint tile;          // output tile side
    uint tiles_x;       // tiles per row
    uint tile_count;    // tiles in the image
    uint tile_base;     // first tile of this dispatch (refine_close_global: waves of tiles)
    uint scratch_words; // refine_close_global: uints of scratch per workgroup
};

// refine_cc_local, refine_cc_edges, refine_cc_compress.
struct CcPush {
    uint width, height;
    uint mode;         // PG_CC_ZERO_4 or PG_CC_LABEL_8
    uint write_sizes;  // refine_cc_local: write each tile-local root's pixel count (others stay 0)
};

// refine_hole_*, refine_lcc_*.
struct PixelPush {
    uint width, height;
    uint table_mask;  // refine_lcc_*: instance hash table slots - 1 (a power of two minus 1)
    uint pad;
};

#ifdef __cplusplus
static_assert(sizeof(ClosePush) == 32);
static_assert(sizeof(CcPush) == 16);
static_assert(sizeof(PixelPush) == 16);
}  // namespace pg::seg::gpu
#endif

#endif

// Layouts and constants shared by the structure ops of nn/ops (serialize, voxelize,
// neighbors, pooling) and their shaders: one definition, no drift. C++ includes it too.
#ifndef PG_NN_INDEX_SHARED_GLSL
#define PG_NN_INDEX_SHARED_GLSL

#ifdef __cplusplus
#include <cstdint>
namespace pg::nn::ops::gpu {
using uint = uint32_t;
#endif

#define PG_INDEX_THREADS 256

// The info buffer (uint words) of voxelize and neighbor_map: per-axis maxima found on the GPU
// fix the bit widths of the packed (batch, x, y, z) keys, so the host never needs them.
#define PG_INFO_MAX_X 0
#define PG_INFO_MAX_Y 1
#define PG_INFO_MAX_Z 2
#define PG_INFO_MAX_BATCH 3
#define PG_INFO_FLAGS 4
#define PG_INFO_COUNT 5  // distinct keys, written by the prefix sum
#define PG_INFO_WORDS 8
#define PG_FLAG_NEGATIVE 1u  // a grid or batch entry is negative
#define PG_FLAG_OVERFLOW 2u  // the widths of batch, x, y, z add up to more than the key's bits

// nn/serialize_codes
struct SerializePush {
    uint n;
    uint depth;    // bits per axis
    uint swap_xy;  // the *-trans orders
    uint hilbert;  // 0: z-order
};

// Passes over n items that need nothing else (bounds, keys, runs, scatters).
struct CountPush {
    uint n;
    uint pad0, pad1, pad2;
};

// nn/voxel_keys: n points, and the bits the caller sorts (64 when it knows no smaller bound).
struct KeyPush {
    uint n;
    uint key_bits;
    uint pad0, pad1;
};

// nn/serialize_keys, nn/pool_codes, nn/pool_grid: n rows, a right shift, a row width.
struct ShiftPush {
    uint n;
    uint shift;
    uint width;
    uint pad;
};

// nn/neighbors_search
struct NeighborPush {
    uint n;
    uint kernel;  // 3 or 5
    uint pad0, pad1;
};

// nn/segment_max
struct SegmentMaxPush {
    uint clusters;
    uint channels;
    uint pad0, pad1;
};

#ifdef __cplusplus
}  // namespace pg::nn::ops::gpu
#endif
#endif

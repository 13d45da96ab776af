// Push-constant layouts and tunables of the GEMM kernels, shared by nn/ops/linear.cpp and the
// shaders: one definition, no drift. Only 32-bit members, so C++ and std430 agree.
#ifndef PG_GEMM_SHARED_GLSL
#define PG_GEMM_SHARED_GLSL

#ifdef __cplusplus
#include <cstdint>
namespace pg::nn::gpu {
using uint = uint32_t;
#endif

// Columns of y per workgroup of the lanes kernels (gemm_lanes.glsl).
#define PG_LANES_NC 32
// Output tile and depth slice of the tiled kernels (gemm_tiled.glsl); 256 invocations, 4x4 each.
#define PG_TILE_M 64
#define PG_TILE_N 64
#define PG_TILE_K 16

// GemmPush.flags
#define PG_GEMM_FIRST 1u     // lanes: this chunk starts the sum (bias, residual) instead of adding to y
#define PG_GEMM_BIAS 2u      // a bias vector is bound
#define PG_GEMM_RESIDUAL 4u  // a residual matrix is bound
#define PG_GEMM_GATHER 8u    // A rows come from x through the neighbour table
#define PG_GEMM_PARTIAL 16u  // tiled: write this split's raw partial sum (split-K)
#define PG_GEMM_GELU 32u     // y = GELU(sum); lanes kernels take it as a shader variant instead

// The A operand is A[m, k] = x[j, k % cin] with j = m (dense) or nbr[m * taps + k / cin]
// (gathered; j < 0 reads zeros). Dense products pass cin = K, taps = 1.
struct GemmPush {
    uint M, N, K;
    uint k0;         // lanes: first column of A in this chunk; tiled: depth per split (rulebook: tap's first column)
    uint flags;
    uint cin, taps;
    uint col_tiles;  // workgroups along N; the group index is row_tile * col_tiles + col_tile
    uint slice_k;    // lanes SPLIT: depth between slices' starts (a multiple of the chunk depth)
};

// y = bias + residual + sum over splits of partial[s] (split-K epilogue).
struct GemmReducePush {
    uint M, N, splits, flags;
};

#ifdef __cplusplus
}  // namespace pg::nn::gpu
#endif
#endif

// Push-constant layouts of the sparse-convolution rulebook kernels, shared by
// nn/ops/sparse_conv.cpp and the shaders. Only 32-bit members, so C++ and std430 agree.
#ifndef PG_CONV_SHARED_GLSL
#define PG_CONV_SHARED_GLSL

#ifdef __cplusplus
#include <cstdint>
namespace pg::nn::gpu {
using uint = uint32_t;
#endif

// nn/conv_rules over the neighbour table nbr [M, taps].
struct ConvRulesPush {
    uint M, taps;
};

// Indirect dispatch arguments per tap: ceil(pairs / rows_per_group) * col_tiles groups, folded
// past `limit` like the host folds direct dispatches.
struct ConvArgsPush {
    uint taps, rows_per_group, col_tiles, limit;
};

// y[M, N] = bias (flags & PG_GEMM_BIAS) or 0, the start of the per-tap sums.
struct ConvInitPush {
    uint M, N, flags;
};

#ifdef __cplusplus
}  // namespace pg::nn::gpu
#endif
#endif

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

// nn/conv_schedule: the row groups of rows_per_group pairs of every tap, numbered back to back
// (the lanes kernels' TAPS variants): schedule[t] is tap t's first (t <= taps, schedule[taps]
// the total), schedule[taps + 1 + r] the tap of row group r.
struct ConvSchedulePush {
    uint taps, rows_per_group;
};

// nn/conv_taps_args: the indirect dispatch of every tap's row groups from the schedule,
// col_tiles workgroups per row group, folded past `limit`.
struct ConvTapsArgsPush {
    uint taps, col_tiles, limit;
};

// nn/conv_reduce: y[m, n] = (bias[n] with flags & PG_GEMM_BIAS, else 0) + the slices of the
// taps whose neighbour exists (nbr[m, t] >= 0), in tap order.
struct ConvReducePush {
    uint M, N, taps, flags;
};

#ifdef __cplusplus
}  // namespace pg::nn::gpu
#endif
#endif

// Push-constant layouts and tunables of the elementwise and per-row kernels of nn/ops
// (elementwise.cpp, norm.cpp), shared by the C++ and the shaders: one definition, no drift.
// Only 32-bit members, so C++ and std430 agree.
//
// `wide`: the kernel moves 8 values at a time (as a u64vec4); the host sets it when the row
// (or the whole tensor) is a multiple of 8 values, and then dispatches an eighth of the threads.
#ifndef PG_NN_ELEMENTWISE_SHARED_GLSL
#define PG_NN_ELEMENTWISE_SHARED_GLSL

#ifdef __cplusplus
#include <cstdint>
namespace pg::nn::ops::gpu {
using uint = uint32_t;
#endif

#define PG_ELEMENTWISE_THREADS 256  // nn/add, gelu, gather_rows, add_gathered
#define PG_NORM_THREADS 64          // nn/layer_norm (a row each), batch_norm
#define PG_BATCH_NORM_ROWS 8u       // rows one batch_norm invocation normalizes (stats read once)

// nn/add: y = a + b over n values.
struct AddPush {
    uint n, wide;
};

// nn/gelu: y = GELU(x), or erf(x) with erf_only, over n values.
struct GeluPush {
    uint n, wide, erf_only;
};

// nn/gather_rows: y[r, :] = x[idx[r], :] over rows of `words` 32-bit words.
struct GatherRowsPush {
    uint rows, words, wide;
};

// nn/add_gathered: y[r, :] = a[r, :] + x[idx[r], :] over rows of c floats.
struct AddGatheredPush {
    uint rows, c, wide;
};

// nn/layer_norm: rows x c, plus a residual when `residual` is set.
struct LayerNormPush {
    uint rows, c, wide, residual;
    float eps;
};

// nn/batch_norm: rows x c, GELU after when `gelu` is set.
struct BatchNormPush {
    uint rows, c, wide, gelu;
    float eps;
};

#ifdef __cplusplus
static_assert(sizeof(AddPush) == 8);
static_assert(sizeof(GeluPush) == 12);
static_assert(sizeof(GatherRowsPush) == 12);
static_assert(sizeof(AddGatheredPush) == 12);
static_assert(sizeof(LayerNormPush) == 20);
static_assert(sizeof(BatchNormPush) == 20);
}  // namespace pg::nn::ops::gpu
#endif
#endif

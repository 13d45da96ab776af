// Push-constant layouts and tunables of the training kernels (nn/train: the backward ops, AdamW,
// drop path), shared by the C++ and the shaders: one definition, no drift. Only 32-bit members,
// so C++ and std430 agree.
//
// Every reduction here runs in a fixed order that depends on the shapes only (rows are cut into
// chunks of a size chosen from the row count, each chunk summed in row order, then the chunk
// sums added in chunk order): no atomics, so gradients are bit-identical from run to run.
#ifndef PG_NN_GRAD_SHARED_GLSL
#define PG_NN_GRAD_SHARED_GLSL

#ifdef __cplusplus
#include <cstdint>
namespace pg::nn::grad::gpu {
using uint = uint32_t;
#endif

#define PG_GRAD_THREADS 256

// nn/grad_transpose_rows(8): out[k, r] = A[m0 + r, k] for r < rows, where A[m, k] = x[m, k]
// (dense, taps = 1, cin = K) or x[nbr[m, k / cin], k % cin] (gathered, zero for -1), and zero for
// m >= M (rows padded to a multiple of 8).
struct TransposeRowsPush {
    uint K, cin, taps, gather;
    uint m0, rows, M;
    uint pad;
};

// Rows per window of the weight gradient: each window is one GEMM over its rows, and the
// windows' products are summed in order (bounded copies, shorter f32 running sums).
#define PG_GRAD_WEIGHT_ROWS 8192

// nn/grad_column_partials modes: the per-element term summed down each column c of row r.
#define PG_COLSUM_PLAIN 0u    // a[r, c]
#define PG_COLSUM_SQDEV 1u    // (a[r, c] - v[c])^2
#define PG_COLSUM_DEV 2u      // a[r, c] * (b[r, c] - v[c])
#define PG_COLSUM_ROWNORM 3u  // a[r, c] * ((b[r, c] - v[3r]) - v[3r+1]) * v[3r+2]  (row shift, mean, 1/std)

// part[chunk, c] = sum over the rows of the chunk of the mode's term.
struct ColumnPartialsPush {
    uint rows, cols, mode, rows_per_chunk;
};

// nn/grad_column_sums (CPU devices): out[c] = scale * the sum over chunks, in order, of the
// chunk sums of nn/grad_column_partials, in one pass.
#define PG_COLSUM_THREADS 8
struct ColumnSumsPush {
    uint rows, cols, mode, rows_per_chunk;
    float scale;
    uint pad0, pad1, pad2;
};

// out[i] = scale * sum over s < splits of part[s * len + i].
struct SumPartialsPush {
    uint len, splits;
    float scale;
    uint pad;
};

// nn/grad_transpose: out[c, t * rows + o] = w[o, t' * cin + c] with t' = taps-1-t (flip) or t.
struct TransposePush {
    uint rows, cin, taps, flip;
};

// Row-wise and elementwise kernels: rows x cols, a float parameter.
struct RowsPush {
    uint rows, cols;
    float eps;
    uint pad;
};

// nn/grad_batch_norm_running: momentum m, batch rows (for the unbiased variance).
struct RunningStatsPush {
    uint cols, rows;
    float momentum;
    uint pad;
};

// nn/grad_group_ptr: R sorted keys (target row of each gathered row), P targets.
struct GroupPush {
    uint rows, targets, cols, pad;
};

// nn/grad_cross_entropy_rows: rows x classes, the ignored label.
struct CrossEntropyPush {
    uint rows, classes;
    int ignore_label;
    uint pad;
};

// nn/grad_lovasz_*: rows x classes, the ignored label, the loss weight.
struct LovaszPush {
    uint rows, classes;
    int ignore_label;
    float scale;
};

// nn/adamw: one AdamW step over up to PG_ADAMW_SETS tensors of count[s] elements, tensor s from
// workgroup first_group[s] (first_group[s] <= first_group[s + 1]; sets past the last have count
// 0); bias1 = 1 - beta1^t, bias2_sqrt = sqrt(1 - beta2^t).
#define PG_ADAMW_SETS 4
struct AdamWPush {
    uint first_group[PG_ADAMW_SETS];
    uint count[PG_ADAMW_SETS];
    float lr, beta1, beta2, eps, weight_decay, bias1, bias2_sqrt, pad;
};

// nn/scale_rows: y[r, c] = x[r, c] * s[r] over n = rows * channels values.
struct ScaleRowsPush {
    uint n, channels;
};

// The per-row values nn/grad_cross_entropy_rows writes ([rows, PG_CE_VALUES]) and their sums.
#define PG_CE_LOSS 0
#define PG_CE_COUNTED 1
#define PG_CE_BAD 2
#define PG_CE_VALUES 3

#ifdef __cplusplus
static_assert(sizeof(AdamWPush) == 64);
static_assert(sizeof(ScaleRowsPush) == 8);
}  // namespace pg::nn::grad::gpu
#endif
#endif

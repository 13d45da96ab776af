#pragma once
// Backward passes of PTv3's dense ops (nn/ops), a training-mode BatchNorm and the softmax
// cross-entropy loss, on the GPU. Each takes the forward's inputs and the gradient of the loss
// with respect to the forward's output (dy), and returns the gradients of its inputs.
//
// Deterministic: no float atomics; every sum runs in an order fixed by the shapes alone
// (shaders/nn/grad_shared.glsl), so on one device the same inputs give bit-identical gradients
// on every run. Matrix products reuse the forward's GEMM kernels (ops::linear, ops::sparse_conv),
// the weight gradient as linear(dyᵀ, xᵀ) over windows of rows.
#include <cstdint>

#include "nn/ops/pooling.h"
#include "nn/ops/sparse_conv.h"
#include "nn/tensor.h"

namespace pg::nn::grad {

// y = x·wᵀ + b (ops::linear, x [M,K], w [N,K]): dx = dy·w [M,K], dw = dyᵀ·x [N,K],
// db = column sums of dy [N]. A fused residual's gradient is dy itself.
struct LinearGrads {
    Tensor dx, dw, db;
};
LinearGrads linear_backward(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Tensor& w, const Tensor& dy);

// Submanifold sparse convolution (ops::sparse_conv with x [P,Cin], nbr [P,T], w [Cout, T*Cin]).
// dw[o, t*Cin + c] = sum_q dy[q,o] x[nbr[q,t], c]; db = column sums of dy; dx[p] = sum of
// W_tᵀ dy[q] over the pairs (q,t) with nbr[q,t] = p.
//
// dx relies on the map being symmetric: nbr[q,t] = p <=> nbr[p, T-1-t] = q (offset t and its
// mirror T-1-t are opposite vectors), which holds when the voxels of each cloud are distinct,
// as after voxelize. Then dx is the same gathered GEMM as the forward, over dy with the per-tap
// transposed weights in mirrored tap order: no scatter, no atomics. With duplicate voxels the
// map is not symmetric and dx is wrong (tests/nn_grad check both facts).
struct ConvGrads {
    Tensor dx, dw, db;
};
ConvGrads sparse_conv_backward(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Tensor& nbr, const Tensor& w,
                               const Tensor& dy, bool with_dx = true);  // false: dx left undefined (x is an input)
// The same over a prebuilt rulebook of the table (ops::build_rulebook): dx reuses the forward's
// instead of building its own.
ConvGrads sparse_conv_backward(vk::CommandList& cmd, Pool& pool, const Tensor& x, const ops::Rulebook& rules,
                               const Tensor& w, const Tensor& dy);

// LayerNorm over channels (ops::layer_norm, x [M,C], biased variance, eps inside the sqrt).
// A fused residual's gradient is dy itself.
struct NormGrads {
    Tensor dx, dgamma, dbeta;
};
NormGrads layer_norm_backward(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Tensor& gamma, const Tensor& dy,
                              float eps);

// BatchNorm1d in training mode over x [M,C] (M >= 2): normalises with the batch statistics
// (mean, biased var) and updates running_mean / running_var [C] in place, PyTorch's way
// (PTv3's BatchNorm1d uses momentum 0.01):
// running = (1 - momentum) * running + momentum * batch, the variance unbiased (var * M/(M-1)).
// The returned mean and var [C] are what batch_norm_backward takes.
struct BatchNormTrain {
    Tensor y, mean, var;
};
BatchNormTrain batch_norm_train(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Tensor& gamma,
                                const Tensor& beta, const Tensor& running_mean, const Tensor& running_var, float eps,
                                float momentum = 0.01f);
// Gradients through the batch statistics too (training mode), from the forward's mean and var.
NormGrads batch_norm_backward(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Tensor& mean, const Tensor& var,
                              const Tensor& gamma, const Tensor& dy, float eps);

// Exact GELU: dx = dy * (Phi(x) + x phi(x)), for x and dy of one shape.
Tensor gelu_backward(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Tensor& dy);

// y = a + b: both gradients are dy (no copy is made).
struct AddGrads {
    Tensor da, db;
};
AddGrads add_backward(const Tensor& dy);

// The rows gathered from each target row, as CSR: for target p, order[ptr[p] .. ptr[p+1]) are
// the rows r with idx[r] = p, ascending. Built once per index and reused by every backward
// through it. Indices outside [0, targets) join no group (their gradient is dropped).
struct RowGroups {
    Tensor order, ptr;  // I32 [R], I32 [targets + 1]
    int64_t targets = 0;
};
// General index idx I32 [R]: a stable sort of (idx[r], r) on the GPU.
RowGroups group_rows(vk::CommandList& cmd, Pool& pool, const Tensor& idx, int64_t targets);
// Pooling clusters already are this CSR for idx = clusters.cluster (members grouped by
// cluster, ascending): no sort.
RowGroups group_rows(const ops::Clusters& clusters);

// y = x[idx] (ops::gather_rows, f32 rows): dx [targets, C] with dx[p] = sum of dy[r] over the
// rows of group p, in ascending r; rows never gathered get 0.
Tensor gather_rows_backward(vk::CommandList& cmd, Pool& pool, const Tensor& dy, const RowGroups& groups);
// The same when idx I32 [R] is a permutation of [0, R) (e.g. a serialization order): one
// scatter, no sort. A non-permutation leaves rows unwritten or written twice.
Tensor gather_rows_backward_permutation(vk::CommandList& cmd, Pool& pool, const Tensor& dy, const Tensor& idx);

// y = a + x[idx] (ops::add_gathered): da = dy, dx = gather_rows_backward(dy, groups of idx).
struct AddGatheredGrads {
    Tensor da, dx;
};
AddGatheredGrads add_gathered_backward(vk::CommandList& cmd, Pool& pool, const Tensor& dy, const RowGroups& groups);

// y = ops::segment_max(x, clusters) (x [N,C], y [M,C]): dy[m,c] goes to the member of cluster m
// holding the max of channel c, the lowest point index among ties; every other entry is 0.
Tensor segment_max_backward(vk::CommandList& cmd, Pool& pool, const Tensor& x, const ops::Clusters& clusters,
                            const Tensor& dy);

// Softmax cross-entropy of logits [M, classes] against labels I32 [M], averaged over the rows
// counted: rows labelled `ignore_label` are skipped, as are rows with a label outside
// [0, classes) (reported in info; PyTorch would raise). With no row counted the loss and the
// gradient are 0 (PyTorch gives NaN). loss F32 [1], dlogits [M, classes], info U32 [2] =
// (rows counted, bad labels); all stay on the GPU.
struct CrossEntropy {
    Tensor loss, dlogits, info;
};
CrossEntropy cross_entropy(vk::CommandList& cmd, Pool& pool, const Tensor& logits, const Tensor& labels,
                           int32_t ignore_label = -1);

// Lovasz-softmax loss of logits [M, classes] against labels I32 [M] (Pointcept's LovaszLoss,
// multiclass mode, over all rows at once): the mean over the classes present among the counted
// rows of the Lovasz extension of the class's Jaccard loss, evaluated at the errors
// |[label == c] - softmax_c|. Rows are left out as cross_entropy leaves them out; with none
// counted the loss and gradient are 0. Both are multiplied by `weight`; loss F32 [1], dlogits
// [M, classes], on the GPU. Ties in error rank by row, so results are bit-identical run to run.
struct Lovasz {
    Tensor loss, dlogits;
};
Lovasz lovasz_softmax(vk::CommandList& cmd, Pool& pool, const Tensor& logits, const Tensor& labels,
                      int32_t ignore_label = -1, float weight = 1.0f);

}  // namespace pg::nn::grad

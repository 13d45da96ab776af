// Softmax cross-entropy loss and its gradient, on the GPU.
#include <algorithm>
#include <stdexcept>
#include <string>

#include "nn/train/grad_ops.h"
#include "nn/train/grad_reduce.h"
#include "shaders/nn/grad_shared.glsl"

namespace pg::nn::grad {

CrossEntropy cross_entropy(vk::CommandList& cmd, Pool& pool, const Tensor& logits, const Tensor& labels,
                           int32_t ignore_label) {
    const char* op = "cross_entropy";
    detail::expect(op, "logits", logits, DType::F32, {-1, -1});
    const int64_t M = logits.dim(0), K = logits.dim(1);
    detail::expect(op, "labels", labels, DType::I32, {M});
    if (K == 0 && M > 0) throw std::invalid_argument(std::string(op) + ": logits " + logits.shape_string() + " have no classes");
    detail::expect_small(op, uint64_t(M) * uint64_t(K));
    detail::expect_small(op, uint64_t(M) * PG_CE_VALUES);
    CrossEntropy ce{pool.empty({1}), pool.empty(logits.shape), pool.empty({2}, DType::U32)};
    gpu::CrossEntropyPush push{uint32_t(M), uint32_t(K), ignore_label, 0};
    Tensor vals = pool.empty({M, PG_CE_VALUES});
    if (M > 0) cmd.dispatch("nn/grad_cross_entropy_rows", {logits, labels, ce.dlogits, vals}, push, vk::ceil_div(M, 64));
    // Sums of (loss, counted, bad) in a fixed order: the same loss on every run.
    Tensor sums = detail::column_sums(cmd, pool, PG_COLSUM_PLAIN, vals, vals, vals, uint64_t(M), PG_CE_VALUES);
    cmd.dispatch("nn/grad_cross_entropy_finish", {sums, ce.dlogits, ce.loss, ce.info}, push,
                 std::max<uint32_t>(1, vk::ceil_div(uint64_t(M) * K, PG_GRAD_THREADS)));
    return ce;
}

}  // namespace pg::nn::grad

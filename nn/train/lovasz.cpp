// Lovasz-softmax loss (Berman et al. 2018, as Pointcept's LovaszLoss in multiclass mode over the
// whole batch) and its gradient, on the GPU: per-class errors sorted by the radix sort of the
// serialization, foreground counted along the sorted runs by the prefix sum.
#include <bit>
#include <stdexcept>
#include <string>

#include "nn/ops/serialize.h"
#include "nn/train/grad_ops.h"
#include "nn/train/grad_reduce.h"
#include "shaders/nn/grad_shared.glsl"

namespace pg::nn::grad {

Lovasz lovasz_softmax(vk::CommandList& cmd, Pool& pool, const Tensor& logits, const Tensor& labels,
                      int32_t ignore_label, float weight) {
    const char* op = "lovasz_softmax";
    detail::expect(op, "logits", logits, DType::F32, {-1, -1});
    const int64_t M = logits.dim(0), K = logits.dim(1);
    detail::expect(op, "labels", labels, DType::I32, {M});
    if (K == 0 && M > 0) throw std::invalid_argument(std::string(op) + ": logits " + logits.shape_string() + " have no classes");
    const uint64_t entries = uint64_t(M) * uint64_t(K);
    detail::expect_small(op, entries + 1);
    Lovasz out{pool.empty({1}), pool.empty(logits.shape)};
    if (entries == 0) {
        cmd.fill(*out.loss.buffer, 0, 0, 4);
        return out;
    }
    const gpu::LovaszPush push{uint32_t(M), uint32_t(K), ignore_label, weight};
    const uint32_t groups = vk::ceil_div(entries + 1, 64);
    Tensor keys = pool.empty({int64_t(entries)}, DType::U64);
    cmd.dispatch("nn/grad_lovasz_keys", {logits, labels, keys}, push, groups);
    // Class in the high word (`classes` for rows left out), inverted error bits in the low one.
    const ops::Sorted sorted = ops::sort_codes(cmd, pool, keys, 32 + int(std::bit_width(uint64_t(K))));
    Tensor fg = pool.empty({int64_t(entries + 1)}, DType::U32), counts = pool.empty({1}, DType::U32);
    cmd.dispatch("nn/grad_lovasz_fg", {logits, labels, sorted.order, fg, counts}, push, groups);
    ops::detail::index_state(pool.context()).scan.exclusive(cmd, *fg.buffer, *fg.buffer, uint32_t(entries + 1));
    Tensor terms = pool.empty({int64_t(entries), 1}), weights = pool.empty({int64_t(entries)});
    cmd.dispatch("nn/grad_lovasz_grad", {logits, labels, sorted.order, fg, counts, terms, weights}, push, groups);
    // The loss in a fixed order: the same value on every run.
    Tensor sum = detail::column_sums(cmd, pool, PG_COLSUM_PLAIN, terms, terms, terms, entries, 1);
    cmd.dispatch("nn/grad_lovasz_logits", {logits, labels, weights, sum, out.dlogits, out.loss}, push,
                 vk::ceil_div(uint64_t(M), 64));
    return out;
}

}  // namespace pg::nn::grad

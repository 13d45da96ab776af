// Backward of the elementwise and index ops (GELU, add, row gathers, cluster max).
#include "nn/train/grad_ops.h"

#include <algorithm>
#include <bit>
#include <stdexcept>
#include <string>

#include "engine/sort/radix_sort.h"
#include "engine/vk/context.h"
#include "nn/train/grad_reduce.h"
#include "shaders/nn/grad_shared.glsl"

namespace pg::nn::grad {

using vk::ceil_div;

namespace {

// The sorter group_rows uses, kept in the context: its scratch must outlive the command lists
// it was recorded into.
struct GradState {
    explicit GradState(vk::Context& ctx) : sort(ctx) {}
    sort::RadixSort sort;
};

}  // namespace

Tensor gelu_backward(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Tensor& dy) {
    const char* op = "gelu_backward";
    detail::expect(op, "x", x, DType::F32, x.shape);
    detail::expect(op, "dy", dy, DType::F32, x.shape);
    const uint64_t n = uint64_t(x.numel());
    detail::expect_small(op, n);
    Tensor dx = pool.empty(x.shape);
    if (n == 0) return dx;
    gpu::RowsPush push{uint32_t(n), 1, 0.0f, 0};
    cmd.dispatch("nn/grad_gelu", {x, dy, dx}, push, ceil_div(n, PG_GRAD_THREADS));
    return dx;
}

AddGrads add_backward(const Tensor& dy) { return {dy, dy}; }

RowGroups group_rows(vk::CommandList& cmd, Pool& pool, const Tensor& idx, int64_t targets) {
    const char* op = "group_rows";
    detail::expect(op, "index", idx, DType::I32, {-1});
    if (targets < 0 || targets >= 0x7FFFFFFF)
        throw std::invalid_argument(std::string(op) + ": target count " + std::to_string(targets) + " out of range");
    const uint64_t R = uint64_t(idx.dim(0));
    detail::expect_small(op, R + 1);
    RowGroups g{pool.empty({int64_t(R)}, DType::I32), pool.empty({targets + 1}, DType::I32), targets};
    gpu::GroupPush push{uint32_t(R), uint32_t(targets), 0, 0};
    if (R == 0) {
        cmd.fill(*g.ptr.buffer, 0u);
        return g;
    }
    Tensor keys = pool.empty({int64_t(R)}, DType::U32);
    cmd.dispatch("nn/grad_group_keys", {idx, keys, g.order}, push, ceil_div(R, PG_GRAD_THREADS));
    // Stable: the rows of a group stay ascending, which fixes the order of their sum.
    const uint32_t key_bits = std::max(1u, uint32_t(std::bit_width(uint64_t(targets))));
    pool.context().attachment<GradState>("nn.grad").sort.sort(cmd, *keys.buffer, *g.order.buffer, uint32_t(R),
                                                               key_bits, sort::KeyWidth::Bits32);
    cmd.dispatch("nn/grad_group_ptr", {keys, g.ptr}, push, ceil_div(R + 1, PG_GRAD_THREADS));
    return g;
}

RowGroups group_rows(const ops::Clusters& clusters) { return {clusters.members, clusters.ptr, clusters.count}; }

Tensor gather_rows_backward(vk::CommandList& cmd, Pool& pool, const Tensor& dy, const RowGroups& groups) {
    const char* op = "gather_rows_backward";
    detail::expect(op, "dy", dy, DType::F32, {-1, -1});
    const int64_t R = dy.dim(0), C = dy.dim(1);
    detail::expect(op, "groups.order", groups.order, DType::I32, {R});
    detail::expect(op, "groups.ptr", groups.ptr, DType::I32, {groups.targets + 1});
    const uint64_t n = uint64_t(groups.targets) * uint64_t(C);
    detail::expect_small(op, n);
    detail::expect_small(op, uint64_t(R) * uint64_t(C));
    Tensor dx = pool.empty({groups.targets, C});
    if (n == 0) return dx;
    gpu::GroupPush push{uint32_t(R), uint32_t(groups.targets), uint32_t(C), 0};
    cmd.dispatch("nn/grad_gather_rows", {dy, groups.order, groups.ptr, dx}, push, ceil_div(n, PG_GRAD_THREADS));
    return dx;
}

Tensor gather_rows_backward_permutation(vk::CommandList& cmd, Pool& pool, const Tensor& dy, const Tensor& idx) {
    const char* op = "gather_rows_backward_permutation";
    detail::expect(op, "dy", dy, DType::F32, {-1, -1});
    const int64_t R = dy.dim(0), C = dy.dim(1);
    detail::expect(op, "index", idx, DType::I32, {R});
    const uint64_t n = uint64_t(R) * uint64_t(C);
    detail::expect_small(op, n);
    Tensor dx = pool.empty({R, C});
    if (n == 0) return dx;
    gpu::GroupPush push{uint32_t(R), uint32_t(R), uint32_t(C), 0};
    cmd.dispatch("nn/grad_scatter_rows", {dy, idx, dx}, push, ceil_div(n, PG_GRAD_THREADS));
    return dx;
}

AddGatheredGrads add_gathered_backward(vk::CommandList& cmd, Pool& pool, const Tensor& dy, const RowGroups& groups) {
    return {dy, gather_rows_backward(cmd, pool, dy, groups)};
}

Tensor segment_max_backward(vk::CommandList& cmd, Pool& pool, const Tensor& x, const ops::Clusters& clusters,
                            const Tensor& dy) {
    const char* op = "segment_max_backward";
    detail::expect(op, "x", x, DType::F32, {-1, -1});
    const int64_t N = x.dim(0), C = x.dim(1), M = clusters.count;
    detail::expect(op, "dy", dy, DType::F32, {M, C});
    detail::expect(op, "clusters.members", clusters.members, DType::I32, {N});
    if (!clusters.ptr.defined() || clusters.ptr.dtype != DType::I32 || clusters.ptr.numel() < M + 1)
        throw std::invalid_argument(std::string(op) + ": clusters.ptr must be i32 with " + std::to_string(M + 1) +
                                    " entries");
    detail::expect_small(op, uint64_t(N) * uint64_t(C));
    Tensor dx = pool.empty(x.shape);
    if (N == 0 || C == 0) return dx;
    // Clusters cover every point; with none (an empty cloud) there is nothing to route.
    if (M == 0) {
        cmd.fill(*dx.buffer, 0u);
        return dx;
    }
    gpu::GroupPush push{uint32_t(N), uint32_t(M), uint32_t(C), 0};
    cmd.dispatch("nn/grad_segment_max", {x, dy, clusters.members, clusters.ptr, dx}, push,
                 ceil_div(uint64_t(M) * C, PG_GRAD_THREADS));
    return dx;
}

}  // namespace pg::nn::grad

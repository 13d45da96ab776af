// Backward of the matrix products (ops::linear, ops::sparse_conv).
#include <algorithm>
#include <stdexcept>
#include <string>

#include "nn/ops/linear.h"
#include "nn/ops/sparse_conv.h"
#include "nn/train/grad_ops.h"
#include "nn/train/grad_reduce.h"
#include "shaders/nn/grad_shared.glsl"

namespace pg::nn::grad {

namespace {

using vk::ceil_div;

// w [rows, taps*cin] -> [cin, taps*rows], taps in mirrored order when `flip`.
Tensor transpose_taps(vk::CommandList& cmd, Pool& pool, const Tensor& w, uint32_t rows, uint32_t cin, uint32_t taps,
                      bool flip) {
    Tensor out = pool.empty({int64_t(cin), int64_t(taps) * rows});
    const uint64_t n = uint64_t(rows) * cin * taps;
    if (n == 0) return out;
    gpu::TransposePush push{rows, cin, taps, flip ? 1u : 0u};
    cmd.dispatch("nn/grad_transpose", {w, out}, push, ceil_div(n, PG_GRAD_THREADS));
    return out;
}

// dW [N, K] = dyᵀ·A over M rows, A = x (nbr null) or x gathered through nbr. It is the forward's
// GEMM on transposed operands, linear(dyᵀ [N, rows], Aᵀ [K, rows]): its kernels are fast on GPUs
// and CPU devices alike, and sum the depth (here the rows) in a fixed order. Rows go in windows
// of PG_GRAD_WEIGHT_ROWS, whose products are then added in window order: smaller transposed
// copies, and f32 sums that drift less than one long running sum over every row.
Tensor weight_grad(vk::CommandList& cmd, Pool& pool, const Tensor& dy, const Tensor& x, const Tensor* nbr, uint32_t M,
                   uint32_t N, uint32_t K, uint32_t cin, uint32_t taps) {
    if (N == 0 || K == 0 || M == 0) {
        Tensor dw = pool.empty({int64_t(N), int64_t(K)});
        if (dw.numel() > 0) cmd.fill(*dw.buffer, 0u);
        return dw;
    }
    const uint32_t windows = ceil_div(M, PG_GRAD_WEIGHT_ROWS);
    detail::expect_small("weight gradient", uint64_t(PG_GRAD_WEIGHT_ROWS) * std::max(N, K));
    detail::expect_small("weight gradient", uint64_t(windows) * N * K);
    // Aᵀ of one window: rows padded to a multiple of 8 with zeros, which add nothing to the product.
    auto transposed = [&](const Tensor& src, const Tensor* map, uint32_t width, uint32_t m0, uint32_t rows) {
        const uint32_t padded = ceil_div(rows, 8) * 8;
        Tensor t = pool.empty({int64_t(width), int64_t(padded)});
        const uint32_t c = map ? cin : width;
        gpu::TransposeRowsPush push{width, c, map ? taps : 1u, map ? 1u : 0u, m0, padded, M, 0};
        const vk::BufferRange table = map ? vk::BufferRange(*map) : vk::BufferRange(src);
        if (width % 8 == 0 && c % 8 == 0)
            cmd.dispatch("nn/grad_transpose_rows8", {src, table, t}, push,
                         ceil_div(uint64_t(width / 8) * (padded / 8), PG_GRAD_THREADS));
        else if (ops::detail::use_lanes(pool.context()))
            cmd.dispatch("nn/grad_transpose_rows_tap", {src, table, t}, push,
                         ceil_div(uint64_t(map ? taps : 1u) * (padded / 8), PG_GRAD_THREADS));
        else
            cmd.dispatch("nn/grad_transpose_rows", {src, table, t}, push, ceil_div(uint64_t(width) * padded, PG_GRAD_THREADS));
        return t;
    };
    // The GEMM spreads its rows over lanes and workgroups: the longer side goes there, and a
    // (small) transpose turns dwᵀ back when that is K. Its fast CPU kernels (linear_deep's depth
    // split) write 8 output columns at a time, so the other side goes there when only it is a
    // multiple of 8: a 2-class head's dW is then one dispatch per window, not one per 64 rows.
    const bool n8 = N % 8 == 0, k8 = K % 8 == 0;
    const bool swap = n8 == k8 ? K > N : n8;
    const uint64_t bytes = uint64_t(N) * K * sizeof(float);
    Tensor dw, part = windows > 1 ? pool.empty({int64_t(windows), int64_t(N) * K}) : Tensor{};
    for (uint32_t w = 0; w < windows; ++w) {
        const uint32_t m0 = w * PG_GRAD_WEIGHT_ROWS, rows = std::min<uint32_t>(M - m0, PG_GRAD_WEIGHT_ROWS);
        Tensor dyt = transposed(dy, nullptr, N, m0, rows), at = transposed(x, nbr, K, m0, rows);
        dw = swap ? ops::linear_deep(cmd, pool, at, dyt) : ops::linear_deep(cmd, pool, dyt, at);
        if (windows > 1) cmd.copy(*dw.buffer, *part.buffer, bytes, 0, w * bytes);
    }
    if (windows > 1) {
        dw = pool.empty(swap ? std::vector<int64_t>{K, N} : std::vector<int64_t>{N, K});
        detail::sum_partials(cmd, part, dw, uint64_t(N) * K, windows);
    }
    return swap ? transpose_taps(cmd, pool, dw, K, N, 1, false) : dw;
}

Tensor zeros(vk::CommandList& cmd, Pool& pool, std::vector<int64_t> shape) {
    Tensor t = pool.empty(std::move(shape));
    if (t.numel() > 0) cmd.fill(*t.buffer, 0u);
    return t;
}

}  // namespace

LinearGrads linear_backward(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Tensor& w, const Tensor& dy) {
    const char* op = "linear_backward";
    detail::expect(op, "x", x, DType::F32, {-1, -1});
    const int64_t M = x.dim(0), K = x.dim(1);
    detail::expect(op, "weight", w, DType::F32, {-1, K});
    const int64_t N = w.dim(0);
    detail::expect(op, "dy", dy, DType::F32, {M, N});
    detail::expect_small(op, uint64_t(M) * uint64_t(std::max(K, N)));
    detail::expect_small(op, uint64_t(N) * uint64_t(K));
    LinearGrads g;
    // dx = dy·w = linear(dy, wᵀ): the forward's GEMM kernels, fed the transposed weight.
    g.dx = N == 0 ? zeros(cmd, pool, {M, K})
                  : ops::linear(cmd, pool, dy, transpose_taps(cmd, pool, w, uint32_t(N), uint32_t(K), 1, false), {});
    g.dw = weight_grad(cmd, pool, dy, x, nullptr, uint32_t(M), uint32_t(N), uint32_t(K), uint32_t(K), 1);
    g.db = detail::column_sums(cmd, pool, PG_COLSUM_PLAIN, dy, dy, dy, uint64_t(M), uint64_t(N));
    return g;
}

namespace {

// dx through `rules` when given (the table's prebuilt rulebook), else through nbr itself.
ConvGrads conv_backward(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Tensor& nbr,
                        const ops::Rulebook* rules, const Tensor& w, const Tensor& dy, bool with_dx) {
    const char* op = "sparse_conv_backward";
    detail::expect(op, "x", x, DType::F32, {-1, -1});
    const int64_t P = x.dim(0), cin = x.dim(1);
    detail::expect(op, "neighbour table", nbr, DType::I32, {P, -1});
    const int64_t T = nbr.dim(1);
    if (w.dtype != DType::F32 || w.shape.size() < 2 || w.numel() != w.dim(0) * T * cin)
        throw std::invalid_argument(std::string(op) + ": weight " + w.shape_string() + " must be f32 [Cout, " +
                                    std::to_string(T) + "*" + std::to_string(cin) + "]");
    const int64_t cout = w.dim(0), K = T * cin;
    detail::expect(op, "dy", dy, DType::F32, {P, cout});
    detail::expect_small(op, uint64_t(P) * uint64_t(std::max({cin, cout, T})));
    detail::expect_small(op, uint64_t(cout) * uint64_t(K));
    ConvGrads g;
    // Submanifold symmetry (grad_ops.h): dx[p] = sum_t W_{T-1-t}ᵀ dy[nbr[p,t]], the forward's
    // gathered GEMM over dy with weights [Cin, T*Cout] in mirrored tap order, over the same table.
    if (with_dx && (cout == 0 || T == 0)) {
        g.dx = zeros(cmd, pool, {P, cin});
    } else if (with_dx) {
        const Tensor wt = transpose_taps(cmd, pool, w, uint32_t(cout), uint32_t(cin), uint32_t(T), true);
        g.dx = rules ? ops::sparse_conv(cmd, pool, dy, *rules, wt, {}) : ops::sparse_conv(cmd, pool, dy, nbr, wt, {});
    }
    g.dw = weight_grad(cmd, pool, dy, x, &nbr, uint32_t(P), uint32_t(cout), uint32_t(K), uint32_t(cin), uint32_t(T));
    g.dw.shape = w.shape;
    g.db = detail::column_sums(cmd, pool, PG_COLSUM_PLAIN, dy, dy, dy, uint64_t(P), uint64_t(cout));
    return g;
}

}  // namespace

ConvGrads sparse_conv_backward(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Tensor& nbr, const Tensor& w,
                               const Tensor& dy, bool with_dx) {
    return conv_backward(cmd, pool, x, nbr, nullptr, w, dy, with_dx);
}

ConvGrads sparse_conv_backward(vk::CommandList& cmd, Pool& pool, const Tensor& x, const ops::Rulebook& rules,
                               const Tensor& w, const Tensor& dy) {
    return conv_backward(cmd, pool, x, rules.nbr, &rules, w, dy, true);
}

}  // namespace pg::nn::grad

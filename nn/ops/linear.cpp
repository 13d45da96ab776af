#include "nn/ops/linear.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "engine/vk/context.h"
#include "nn/ops/elementwise.h"
#include "shaders/nn/gemm_shared.glsl"

namespace pg::nn::ops {

namespace {

GemmPath g_path = GemmPath::Auto;

// Largest index a shader computes in 32-bit arithmetic.
constexpr uint64_t kMaxIndex = 0xFFFFFFFFull;

// The A operand: x itself, or x's rows gathered through nbr (gemm_shared.glsl).
struct Gemm {
    const Tensor& x;
    const Tensor* nbr;  // null when dense
    const Tensor& w;
    const Tensor& bias;
    const Tensor& residual;
    uint32_t M, N, K, cin, taps;
    bool gelu = false;
};

using vk::ceil_div;

// The lanes kernels there are (shaders/nn/linear_lanes_*.comp) and what each was compiled for
// (gemm_lanes.glsl's WG, KC, A_VEC, Y_VEC, GELU): one list to read, and a combination that was
// never compiled fails here, by name.
struct LanesVariant {
    uint32_t wg, kc;
    bool a_vec, y_vec, gelu;
    const char* shader;
    bool seg8 = false;  // A_SEG 8: gathered rows of cin % 8 == 0 read 8 floats per neighbour lookup
};
constexpr LanesVariant kLanesVariants[] = {
    {64, 32, false, false, false, "nn/linear_lanes_w64_k32_aone_yone"},
    {64, 32, false, true, false, "nn/linear_lanes_w64_k32_aone_yvec"},
    {64, 32, true, false, false, "nn/linear_lanes_w64_k32_avec_yone"},
    {64, 32, true, true, false, "nn/linear_lanes_w64_k32_avec_yvec"},
    {64, 32, true, true, true, "nn/linear_lanes_w64_k32_avec_yvec_gelu"},
    {64, 64, true, false, false, "nn/linear_lanes_w64_k64_avec_yone"},
    {64, 64, true, true, false, "nn/linear_lanes_w64_k64_avec_yvec"},
    {64, 64, true, true, true, "nn/linear_lanes_w64_k64_avec_yvec_gelu"},
    {256, 32, false, false, false, "nn/linear_lanes_w256_k32_aone_yone"},
    {256, 32, false, true, false, "nn/linear_lanes_w256_k32_aone_yvec"},
    {256, 32, true, false, false, "nn/linear_lanes_w256_k32_avec_yone"},
    {256, 32, true, true, false, "nn/linear_lanes_w256_k32_avec_yvec"},
    {256, 32, true, true, true, "nn/linear_lanes_w256_k32_avec_yvec_gelu"},
    {256, 64, true, false, false, "nn/linear_lanes_w256_k64_avec_yone"},
    {256, 64, true, true, false, "nn/linear_lanes_w256_k64_avec_yvec"},
    {256, 64, true, true, true, "nn/linear_lanes_w256_k64_avec_yvec_gelu"},
    {64, 32, true, true, false, "nn/linear_lanes_w64_k32_aseg8_yvec", true},
    {64, 64, true, true, false, "nn/linear_lanes_w64_k64_aseg8_yvec", true},
    {256, 32, true, true, false, "nn/linear_lanes_w256_k32_aseg8_yvec", true},
    {256, 64, true, true, false, "nn/linear_lanes_w256_k64_aseg8_yvec", true},
};

const char* lanes_shader(uint32_t wg, uint32_t kc, bool a_vec, bool y_vec, bool gelu, bool seg8 = false) {
    for (const LanesVariant& v : kLanesVariants)
        if (v.wg == wg && v.kc == kc && v.a_vec == a_vec && v.y_vec == y_vec && v.gelu == gelu && v.seg8 == seg8)
            return v.shader;
    throw std::logic_error("linear: no lanes kernel for " + std::to_string(wg) + " rows, depth " + std::to_string(kc) +
                           (a_vec ? ", vector A" : ", scalar A") + (seg8 ? " in 8-column lookups" : "") +
                           (y_vec ? ", vector y" : ", scalar y") + (gelu ? ", GELU" : ""));
}

void expect_f32(const Tensor& t, const char* op, const char* what) {
    if (t.dtype != DType::F32)
        throw std::invalid_argument(std::string(op) + ": " + what + " must be f32, got " + dtype_name(t.dtype));
}

void check_size(uint64_t n, const char* op) {
    if (n > kMaxIndex) throw std::invalid_argument(std::string(op) + ": tensor too large for 32-bit indexing");
}

uint32_t flags_of(const Gemm& g) {
    return (g.bias.defined() ? PG_GEMM_BIAS : 0u) | (g.residual.defined() ? PG_GEMM_RESIDUAL : 0u) |
           (g.nbr ? PG_GEMM_GATHER : 0u) | (g.gelu ? PG_GEMM_GELU : 0u);
}

// Rows per workgroup of the lanes kernels: fewer idle lanes for short matrices.
uint32_t lanes_rows(uint64_t M) { return M <= 128 ? 64 : 256; }

// lanes: one dispatch per depth chunk of 64 (32 for a short last one), each accumulating in y.
// Returns false when GELU is still to be applied (the common variants have it built in).
bool run_lanes(vk::CommandList& cmd, const Gemm& g, const Tensor& y) {
    const uint32_t wg = lanes_rows(g.M);
    const bool y_vec = g.N % 8 == 0;
    // Gathered rows of 8 or 24 channels: a neighbour lookup per 8 columns instead of one per
    // 32, still 8-float loads instead of a lookup and a load per column (variants: vector y only).
    const bool seg8 = g.nbr && g.cin % 8 == 0 && g.cin % 32 != 0 && y_vec && !g.gelu;
    const bool a_vec = g.K % 8 == 0 && g.K > 0 && (g.nbr ? g.cin % 32 == 0 || seg8 : g.cin % 8 == 0);
    const bool fused_gelu = g.gelu && a_vec && y_vec;  // the variants that exist (kLanesVariants)
    gpu::GemmPush push{g.M, g.N, g.K, 0, 0, g.cin, g.taps, ceil_div(g.N, PG_LANES_NC)};
    const uint64_t groups = uint64_t(ceil_div(g.M, wg)) * push.col_tiles;
    const Tensor& bias = g.bias.defined() ? g.bias : g.w;  // unused bindings get any buffer
    const Tensor& res = g.residual.defined() ? g.residual : g.x;
    const Tensor& nbr = g.nbr ? *g.nbr : g.x;
    uint32_t k0 = 0;
    do {
        // Scalar A loads make big shaders that buy little from deeper chunks: 32 for them.
        const uint32_t kc = a_vec && g.K - k0 > 32 ? 64 : 32;
        const bool last = k0 + kc >= g.K;
        const char* shader = lanes_shader(wg, kc, a_vec, y_vec, last && fused_gelu, seg8);
        push.k0 = k0;
        push.flags = flags_of(g) | (k0 == 0 ? PG_GEMM_FIRST : 0u);
        cmd.dispatch(shader, {g.x, g.w, bias, res, y, nbr}, push, groups);
        k0 += kc;
    } while (k0 < g.K);
    return !g.gelu || fused_gelu;
}

// tiled: 64x64 tiles; split-K when there are few tiles and a deep K, so the GPU fills up.
void run_tiled(vk::CommandList& cmd, Pool& pool, const Gemm& g, const Tensor& y) {
    const uint32_t tiles_m = ceil_div(g.M, PG_TILE_M), tiles_n = ceil_div(g.N, PG_TILE_N);
    const uint64_t tiles = uint64_t(tiles_m) * tiles_n;
    uint32_t splits = 1;
    if (tiles < 64 && g.K >= 1024)
        splits = uint32_t(std::clamp<uint64_t>(std::min<uint64_t>(g.K / 512, 128 / tiles), 1, 32));
    const uint32_t k_per = ceil_div(ceil_div(g.K, splits), PG_TILE_K) * PG_TILE_K;
    if (splits > 1) splits = ceil_div(g.K, k_per);

    const Tensor& bias = g.bias.defined() ? g.bias : g.w;
    const Tensor& res = g.residual.defined() ? g.residual : g.x;
    const Tensor& nbr = g.nbr ? *g.nbr : g.x;
    gpu::GemmPush push{g.M, g.N, g.K, k_per, flags_of(g), g.cin, g.taps, tiles_n};
    if (splits == 1) {
        cmd.dispatch("nn/linear", {g.x, g.w, bias, res, y, nbr}, push, tiles);
        return;
    }
    check_size(uint64_t(splits) * g.M * g.N, "linear");
    Tensor part = pool.empty({int64_t(splits), int64_t(g.M), int64_t(g.N)});
    push.flags |= PG_GEMM_PARTIAL;
    cmd.dispatch("nn/linear", {g.x, g.w, bias, res, part, nbr}, push, tiles * splits);
    gpu::GemmReducePush rp{g.M, g.N, splits, flags_of(g)};
    cmd.dispatch("nn/linear_reduce", {part, bias, res, y}, rp, ceil_div(uint64_t(g.M) * g.N, 256));
}

Tensor run(vk::CommandList& cmd, Pool& pool, const Gemm& g, std::vector<int64_t> out_shape) {
    Tensor y = pool.empty(std::move(out_shape));
    if (g.M == 0 || g.N == 0) return y;
    if (!detail::use_lanes(pool.context())) {
        run_tiled(cmd, pool, g, y);
    } else if (!run_lanes(cmd, g, y)) {
        return gelu(cmd, pool, y);
    }
    return y;
}

void check_bias_residual(const char* op, const Tensor& bias, const Tensor& residual, int64_t M, int64_t N,
                         const std::vector<int64_t>& out_shape) {
    if (bias.defined()) {
        expect_f32(bias, op, "bias");
        if (bias.numel() != N || bias.shape.size() != 1)
            throw std::invalid_argument(std::string(op) + ": bias " + bias.shape_string() + " must be [" +
                                        std::to_string(N) + "]");
    }
    if (residual.defined()) {
        expect_f32(residual, op, "residual");
        if (residual.shape != out_shape)
            throw std::invalid_argument(std::string(op) + ": residual " + residual.shape_string() +
                                        " must match the output [" + std::to_string(M) + "," + std::to_string(N) + "]");
    }
}

}  // namespace

void set_gemm_path(GemmPath path) { g_path = path; }
GemmPath gemm_path() { return g_path; }

Tensor linear(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Tensor& w, const Tensor& bias,
              const Tensor& residual, Activation act) {
    expect_f32(x, "linear", "x");
    expect_f32(w, "linear", "weight");
    if (w.shape.size() != 2) throw std::invalid_argument("linear: weight " + w.shape_string() + " must be [N, K]");
    if (x.shape.size() != 1 && x.shape.size() != 2)
        throw std::invalid_argument("linear: x " + x.shape_string() + " must be [M, K] or [K]");
    const int64_t K = x.dim(-1), M = x.shape.size() == 2 ? x.dim(0) : 1, N = w.dim(0);
    if (w.dim(1) != K)
        throw std::invalid_argument("linear: x " + x.shape_string() + " and weight " + w.shape_string() +
                                    " disagree on K");
    std::vector<int64_t> out = x.shape.size() == 2 ? std::vector<int64_t>{M, N} : std::vector<int64_t>{N};
    check_bias_residual("linear", bias, residual, M, N, out);
    check_size(uint64_t(M) * uint64_t(std::max(K, N)), "linear");
    check_size(uint64_t(N) * uint64_t(K), "linear");
    if (act != Activation::None && residual.defined())
        throw std::invalid_argument("linear: an activation and a residual together are not supported");
    Gemm g{x, nullptr, w, bias, residual, uint32_t(M), uint32_t(N), uint32_t(K), uint32_t(K), 1, act == Activation::Gelu};
    return run(cmd, pool, g, std::move(out));
}

Tensor linear_deep(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Tensor& w, uint64_t max_partial_floats) {
    static const Tensor none;
    if (!detail::use_lanes(pool.context()) || x.shape.size() != 2 || w.shape.size() != 2 || x.dim(1) != w.dim(1))
        return linear(cmd, pool, x, w, none);
    expect_f32(x, "linear", "x");
    expect_f32(w, "linear", "weight");
    const uint64_t M = uint64_t(x.dim(0)), N = uint64_t(w.dim(0)), K = uint64_t(x.dim(1));
    constexpr uint32_t kc = 64;
    // The split kernels read A and W 8 floats at a time and write y rows 8 at a time.
    const bool shaped = K % 8 == 0 && N % 8 == 0 && M > 0 && N > 0;
    const uint64_t slices = std::min<uint64_t>(ceil_div(K, kc), max_partial_floats / std::max<uint64_t>(M * N, 1));
    if (!shaped || slices < 2) return linear(cmd, pool, x, w, none);
    check_size(M * K, "linear");
    check_size(N * K, "linear");
    check_size(slices * M * N, "linear");
    // Each workgroup takes `per` chunks of 64 (one dispatch per chunk); slice s of a dispatch
    // starts at chunk s * per, so `slices` partial sums cover the depth.
    const uint64_t per = ceil_div(ceil_div(K, kc), slices);
    const uint64_t used = ceil_div(ceil_div(K, kc), per);
    const uint32_t wg = lanes_rows(M);
    const char* shader = wg == 64 ? "nn/linear_lanes_w64_k64_avec_yvec_split" : "nn/linear_lanes_w256_k64_avec_yvec_split";
    Tensor part = pool.empty({int64_t(used), int64_t(M), int64_t(N)});
    gpu::GemmPush push{uint32_t(M), uint32_t(N), uint32_t(K), 0, 0, uint32_t(K), 1, ceil_div(uint32_t(N), PG_LANES_NC),
                       uint32_t(per * kc)};
    const uint64_t tiles = uint64_t(ceil_div(uint32_t(M), wg)) * push.col_tiles;
    for (uint64_t c = 0; c < per; ++c) {
        // Chunk c of every slice; a slice's later chunks add to its partial sum.
        push.k0 = uint32_t(c * kc);
        push.flags = c == 0 ? PG_GEMM_FIRST : 0u;
        cmd.dispatch(shader, {x, w, w, x, part, x}, push, tiles * used);
    }
    Tensor y = pool.empty({int64_t(M), int64_t(N)});
    gpu::GemmReducePush rp{uint32_t(M), uint32_t(N), uint32_t(used), 0};
    cmd.dispatch("nn/linear_reduce", {part, w, x, y}, rp, ceil_div(M * N, 256));
    return y;
}

namespace detail {

bool use_lanes(vk::Context& ctx) {
    switch (g_path) {
    case GemmPath::Lanes: return true;
    case GemmPath::Tiled: return false;
    case GemmPath::Auto: break;
    }
    return ctx.info().type == VK_PHYSICAL_DEVICE_TYPE_CPU;
}

Tensor gathered_conv(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Tensor& nbr, const Tensor& w,
                     const Tensor& bias) {
    const int64_t cin = x.dim(1), M = nbr.dim(0), T = nbr.dim(1), N = w.dim(0);
    static const Tensor none;
    Gemm g{x, &nbr, w, bias, none, uint32_t(M), uint32_t(N), uint32_t(T * cin), uint32_t(cin), uint32_t(T)};
    if (T == 0 || cin == 0) g.K = 0;
    return run(cmd, pool, g, {M, N});
}

}  // namespace detail

}  // namespace pg::nn::ops

#include "nn/ops/sparse_conv.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "engine/vk/context.h"
#include "nn/ops/linear.h"
#include "shaders/nn/conv_shared.glsl"
#include "shaders/nn/gemm_shared.glsl"

namespace pg::nn::ops {

namespace {

constexpr uint64_t kMaxIndex = 0xFFFFFFFFull;  // shaders index in 32 bits

using vk::ceil_div;

void check_size(uint64_t n) {
    if (n > kMaxIndex) throw std::invalid_argument("sparse_conv: tensor too large for 32-bit indexing");
}

// Throws unless x [P, Cin] f32, nbr [M, T] i32, w [Cout, T*Cin] (or [Cout, kx, ky, kz, Cin])
// f32 and bias [Cout] f32 or undefined fit together.
void check_conv(const Tensor& x, const Tensor& nbr, const Tensor& w, const Tensor& bias) {
    if (x.dtype != DType::F32 || w.dtype != DType::F32)
        throw std::invalid_argument(std::string("sparse_conv: x and weight must be f32, got ") + dtype_name(x.dtype) +
                                    " and " + dtype_name(w.dtype));
    if (nbr.dtype != DType::I32)
        throw std::invalid_argument(std::string("sparse_conv: neighbour table must be i32, got ") + dtype_name(nbr.dtype));
    if (x.shape.size() != 2) throw std::invalid_argument("sparse_conv: x " + x.shape_string() + " must be [P, Cin]");
    if (nbr.shape.size() != 2)
        throw std::invalid_argument("sparse_conv: neighbour table " + nbr.shape_string() + " must be [M, T]");
    const int64_t P = x.dim(0), cin = x.dim(1), M = nbr.dim(0), T = nbr.dim(1);
    if (w.shape.size() < 2 || w.numel() != w.dim(0) * T * cin)
        throw std::invalid_argument("sparse_conv: weight " + w.shape_string() + " must be [Cout, " +
                                    std::to_string(T) + "*" + std::to_string(cin) + "]");
    const int64_t N = w.dim(0);
    if (bias.defined() && (bias.dtype != DType::F32 || bias.shape != std::vector<int64_t>{N}))
        throw std::invalid_argument("sparse_conv: bias " + bias.shape_string() + " must be f32 [" + std::to_string(N) +
                                    "]");
    check_size(uint64_t(P) * uint64_t(cin));
    check_size(uint64_t(M) * uint64_t(std::max(T, N)));
    check_size(uint64_t(N) * uint64_t(T) * uint64_t(cin));
}

ConvPath g_path = ConvPath::Auto;

// Whether to convolve over a rulebook rather than with the gathered GEMM. The lanes rulebook
// kernels read A and y 8 floats at a time, in chunks of 16 to 64 columns within a tap (the
// stem's Cin = 2 stays gathered: per tap, y traffic would outweigh the products). On lavapipe
// the rulebook wins 1.5-4x at every PTv3 level. On GPUs one gathered dispatch keeps every SM
// busy while the per-tap dispatches of small tables would not (not measured: no GPU was at
// hand), so they get the rulebook only for large tables, where skipping the missing
// neighbours' products must pay.
bool use_rulebook(vk::Context& ctx, int64_t M, int64_t cin, int64_t N) {
    if (g_path == ConvPath::Gathered || cin == 0) return false;
    if (detail::use_lanes(ctx)) return cin % 16 == 0 && N % 8 == 0;
    return g_path == ConvPath::Rulebook || M >= 65536;
}

// Lanes kernels take one pair per invocation; a tap holds about M/4 to M/2 pairs on surfaces,
// and small groups leave fewer lanes idle on short tables.
uint32_t lanes_rows_per_group(int64_t M) { return M <= 128 ? 32 : M <= 512 ? 128 : 256; }

// The deepest chunk that divides Cin: each chunk re-reads and re-writes the rows of y. Deeper
// ones run faster still (128: -20% at Cin 256) but take llvmpipe seconds to compile (128: 2.5 s,
// 256: 10 s, 64: 0.5 s), paid again by every process.
uint32_t lanes_chunk(int64_t cin) {
    uint32_t kc = 64;
    while (cin % kc) kc /= 2;
    return kc;
}

// The lanes rulebook kernels there are (shaders/nn/conv_lanes_*.comp): pairs per workgroup and
// chunk depth are compile-time constants of each (gemm_lanes.glsl's WG and KC).
struct ConvLanesVariant {
    uint32_t wg, kc;
    const char* shader;
};
constexpr ConvLanesVariant kConvLanesVariants[] = {
    {32, 16, "nn/conv_lanes_w32_k16"},
    {32, 32, "nn/conv_lanes_w32_k32"},
    {32, 64, "nn/conv_lanes_w32_k64"},
    {128, 16, "nn/conv_lanes_w128_k16"},
    {128, 32, "nn/conv_lanes_w128_k32"},
    {128, 64, "nn/conv_lanes_w128_k64"},
    {256, 16, "nn/conv_lanes_w256_k16"},
    {256, 32, "nn/conv_lanes_w256_k32"},
    {256, 64, "nn/conv_lanes_w256_k64"},
};

// The lanes kernel of wg pairs per workgroup and chunk depth kc, one tap a dispatch or all taps
// (gemm_lanes.glsl's TAPS).
std::string conv_lanes_shader(uint32_t wg, uint32_t kc, bool taps) {
    for (const ConvLanesVariant& v : kConvLanesVariants)
        if (v.wg == wg && v.kc == kc) return std::string(v.shader) + (taps ? "_taps" : "_tap");
    throw std::logic_error("sparse_conv: no lanes kernel for " + std::to_string(wg) + " pairs, depth " +
                           std::to_string(kc));
}

// On CPU drivers a convolution whose taps' slices hold at most this many floats (16 MiB) runs
// every tap in one dispatch. Small tables fill a few row groups per tap, so a dispatch per tap
// mostly paid its fixed cost and kept one core busy; large ones pay for the slices' traffic,
// taps x rows x channels written and read again, where a dispatch per tap adds into y in cache.
// (Lavapipe, GPU ms of one convolution, per tap -> all taps: 2048 x 16 channels 3.5-5.1 -> 3.1-3.5,
// 512 x 32 2.9-4.3 -> 1.3-1.6, 128 x 32 1.5-2.5 -> 0.6-0.7; but 3880 x 64, 6.7 M floats of
// slices, 16-20 -> 22-23. The tiny config's training step: 585 -> 70 convolution dispatches,
// conv + conv backward medians 168 -> 141 ms.)
constexpr uint64_t kMaxPartialFloats = uint64_t(1) << 22;

bool all_taps(int64_t M, int64_t T, int64_t N) { return uint64_t(M) * uint64_t(T) * uint64_t(N) <= kMaxPartialFloats; }

bool rulebook_in_range(vk::Context& ctx, int64_t M, int64_t T) {
    return uint64_t(M) * uint64_t(T) * 8 <= ctx.info().max_storage_buffer_range;
}

// Lanes kernels, every tap in one dispatch per depth chunk (sized by the rulebook's schedule):
// each tap's products go to its own slice of `part` (an output row appears at most once per tap,
// so no two lanes write one value), and nn/conv_reduce adds the slices onto the bias in tap order.
void lanes_all_taps(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Rulebook& rules, const Tensor& w,
                    const Tensor& bias, const Tensor& y) {
    const int64_t cin = x.dim(1), M = rules.rows(), T = rules.taps(), N = w.dim(0);
    vk::Context& ctx = pool.context();
    const uint32_t kc = lanes_chunk(cin);
    const std::string shader = conv_lanes_shader(lanes_rows_per_group(M), kc, true);
    const uint32_t col_tiles = ceil_div(uint64_t(N), PG_LANES_NC);
    Tensor part = pool.empty({T, M, N});
    Tensor args = pool.empty({3}, DType::U32);
    cmd.dispatch("nn/conv_taps_args", {rules.schedule, args},
                 gpu::ConvTapsArgsPush{uint32_t(T), col_tiles, ctx.max_group_count_x()}, 1);
    gpu::GemmPush push{uint32_t(M), uint32_t(N), uint32_t(T * cin), 0, 0, uint32_t(cin), uint32_t(T), col_tiles};
    for (int64_t k = 0; k < cin; k += kc) {
        push.k0 = uint32_t(k);
        push.flags = k == 0 ? PG_GEMM_FIRST : 0u;
        cmd.dispatch_indirect(shader, {x, w, w, x, part, rules.pairs, rules.counts, rules.schedule}, push, *args.buffer, 0);
    }
    const gpu::ConvReducePush rp{uint32_t(M), uint32_t(N), uint32_t(T), bias.defined() ? PG_GEMM_BIAS : 0u};
    cmd.dispatch("nn/conv_reduce", {part, rules.nbr, bias.defined() ? bias : w, y}, rp, ceil_div(uint64_t(M) * N / 4, 256));
}

}  // namespace

void set_conv_path(ConvPath path) { g_path = path; }
ConvPath conv_path() { return g_path; }

Rulebook build_rulebook(vk::CommandList& cmd, Pool& pool, const Tensor& nbr) {
    if (nbr.dtype != DType::I32 || nbr.shape.size() != 2)
        throw std::invalid_argument("build_rulebook: neighbour table " + nbr.shape_string() + " must be i32 [M, T]");
    const int64_t M = nbr.dim(0), T = nbr.dim(1), n = M * T;
    check_size(uint64_t(n));
    if (!rulebook_in_range(pool.context(), M, T))
        throw std::invalid_argument("build_rulebook: neighbour table " + nbr.shape_string() +
                                    " has more slots than one storage buffer holds");
    Rulebook r{nbr, pool.empty({T, M, 2}, DType::U32), pool.empty({T}, DType::U32)};
    if (T > 0) cmd.fill(*r.counts.buffer, 0);
    if (n > 0)
        cmd.dispatch("nn/conv_rules", {nbr, r.counts, r.pairs}, gpu::ConvRulesPush{uint32_t(M), uint32_t(T)},
                     uint64_t(ceil_div(uint64_t(M), 256)) * uint64_t(T));
    if (n > 0 && all_taps(M, T, 8)) {
        // For the all-taps lanes kernels, where some convolution over the table may take them (a
        // GPU builds it too: one invocation, and tests move rulebooks between kernel families).
        // Each tap's pairs fill at most ceil(M / wg) row groups.
        const uint32_t wg = lanes_rows_per_group(M);
        r.schedule = pool.empty({2 * T + 1 + int64_t(ceil_div(uint64_t(M), wg)) * T}, DType::U32);
        cmd.dispatch("nn/conv_schedule", {r.counts, r.schedule}, gpu::ConvSchedulePush{uint32_t(T), wg}, 1);
    }
    return r;
}

Tensor sparse_conv(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Rulebook& rules, const Tensor& w,
                   const Tensor& bias) {
    check_conv(x, rules.nbr, w, bias);
    vk::Context& ctx = pool.context();
    const int64_t cin = x.dim(1), M = rules.rows(), T = rules.taps(), N = w.dim(0);
    if (!use_rulebook(ctx, M, cin, N)) return detail::gathered_conv(cmd, pool, x, rules.nbr, w, bias);
    Tensor y = pool.empty({M, N});
    if (M == 0 || N == 0) return y;
    // y = bias (or 0): where a dispatch per tap adds into y, and all of y without taps.
    const auto init_y = [&] {
        const gpu::ConvInitPush init{uint32_t(M), uint32_t(N), bias.defined() ? PG_GEMM_BIAS : 0u};
        cmd.dispatch("nn/conv_init", {bias.defined() ? bias : w, y}, init, ceil_div(uint64_t(M) * N, 256));
    };
    if (T == 0) {
        init_y();
        return y;
    }

    const bool lanes = detail::use_lanes(ctx);
    if (lanes && all_taps(M, T, N)) {
        lanes_all_taps(cmd, pool, x, rules, w, bias, y);
        return y;
    }
    // One GEMM per tap over its pairs, each adding into y, sized on the GPU (indirect): taps
    // without pairs are free.
    init_y();
    const uint32_t wg = lanes ? lanes_rows_per_group(M) : PG_TILE_M;
    const uint32_t col_tiles = ceil_div(uint64_t(N), lanes ? PG_LANES_NC : PG_TILE_N);
    Tensor args = pool.empty({3 * T}, DType::U32);
    cmd.dispatch("nn/conv_args", {rules.counts, args}, gpu::ConvArgsPush{uint32_t(T), wg, col_tiles, ctx.max_group_count_x()},
                 ceil_div(uint64_t(T), 64));
    // Lanes kernels take one depth chunk (within a tap) per dispatch; tiled ones walk the tap.
    const uint32_t kc = lanes ? lanes_chunk(cin) : uint32_t(cin);
    const std::string shader = lanes ? conv_lanes_shader(wg, kc, false) : "nn/conv_tiled";
    gpu::GemmPush push{uint32_t(M), uint32_t(N), uint32_t(T * cin), 0, 0, uint32_t(cin), uint32_t(T), col_tiles};
    for (int64_t t = 0; t < T; ++t)
        for (int64_t k = 0; k < cin; k += kc) {
            push.k0 = uint32_t(t * cin + k);
            cmd.dispatch_indirect(shader, {x, w, w, x, y, rules.pairs, rules.counts}, push, *args.buffer,
                                  VkDeviceSize(t) * 12);
        }
    return y;
}

Tensor sparse_conv(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Tensor& nbr, const Tensor& w,
                   const Tensor& bias) {
    check_conv(x, nbr, w, bias);
    vk::Context& ctx = pool.context();
    const int64_t M = nbr.dim(0), T = nbr.dim(1), cin = x.dim(1), N = w.dim(0);
    if (use_rulebook(ctx, M, cin, N) && rulebook_in_range(ctx, M, T))
        return sparse_conv(cmd, pool, x, build_rulebook(cmd, pool, nbr), w, bias);
    return detail::gathered_conv(cmd, pool, x, nbr, w, bias);
}

}  // namespace pg::nn::ops

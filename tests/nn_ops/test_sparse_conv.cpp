// Sparse convolution over a rulebook (nn/ops/sparse_conv.h) against the double CPU reference,
// on both kernel families, and the rulebook itself against its CPU reference.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

#include "nn/ops/linear.h"
#include "nn/ops/neighbors.h"
#include "nn/ops/sparse_conv.h"
#include "tests/gpu_fixture.h"
#include "tests/reference/nn_dense_ref.h"

using namespace pg;
using nn::DType;
using nn::Tensor;
namespace ref = pg::test::ref;
using nn::ops::ConvPath;
using nn::ops::GemmPath;

namespace {

// Sets the kernel family and convolution algorithm; back to automatic when a test ends.
struct PathScope {
    PathScope(GemmPath g, ConvPath c) {
        nn::ops::set_gemm_path(g);
        nn::ops::set_conv_path(c);
    }
    ~PathScope() {
        nn::ops::set_gemm_path(GemmPath::Auto);
        nn::ops::set_conv_path(ConvPath::Auto);
    }
};

// A random table: each slot missing with probability `missing`, else a random row of P.
std::vector<int32_t> random_table(int64_t M, int64_t T, int64_t P, double missing, uint32_t seed) {
    std::mt19937 rng(seed);
    std::vector<int32_t> nbr(size_t(M * T));
    for (auto& j : nbr)
        j = P == 0 || std::uniform_real_distribution<double>(0, 1)(rng) < missing ? -1 : int32_t(rng() % uint32_t(P));
    return nbr;
}

// Same tolerance as test_linear.cpp: 3 ulps * sqrt(K) of the terms' magnitude.
void check_close(const std::vector<float>& got, const std::vector<double>& want, const std::vector<double>& mag,
                 int64_t K) {
    REQUIRE(got.size() == want.size());
    double worst = 0;
    size_t at = 0;
    for (size_t i = 0; i < got.size(); ++i) {
        const double r = std::fabs(double(got[i]) - want[i]) / (2e-7 * std::sqrt(double(K) + 1.0) * mag[i] + 1e-6);
        if (!(r <= worst)) {
            worst = r;
            at = i;
        }
    }
    INFO("worst at " << at << ": got " << got[at] << ", want " << want[at] << " (error / tolerance " << worst << ")");
    CHECK(worst <= 1.0);
}

// Convolves random x, w, bias over the rulebook of `nbr` and compares with the reference.
void check_conv(nn::Pool& pool, const nn::ops::Rulebook& rules, const std::vector<int32_t>& nbr, int64_t P,
                int64_t cin, int64_t cout, bool bias, uint32_t seed) {
    const int64_t M = rules.rows(), T = rules.taps();
    INFO("P=" << P << " M=" << M << " T=" << T << " Cin=" << cin << " Cout=" << cout << (bias ? " bias" : ""));
    auto x = ref::random_uniform(size_t(P * cin), seed), w = ref::random_uniform(size_t(cout * T * cin), seed + 1);
    auto b = bias ? ref::random_uniform(size_t(cout), seed + 2) : std::vector<float>{};
    Tensor tx = nn::upload_tensor(pool, x, {P, cin}, DType::F32);
    Tensor tw = nn::upload_tensor(pool, w, {cout, T * cin}, DType::F32);
    Tensor tb = bias ? nn::upload_tensor(pool, b, {cout}, DType::F32) : Tensor{};
    vk::CommandList cmd(pool.context());
    Tensor y = nn::ops::sparse_conv(cmd, pool, tx, rules, tw, tb);
    cmd.submit_and_wait();
    CHECK(y.shape == std::vector<int64_t>{M, cout});
    const auto a = ref::gather_conv_input(x, nbr, M, T, cin);
    check_close(nn::download_tensor<float>(pool.context(), y), ref::linear(a, w, b, {}, M, T * cin, cout),
                ref::linear_magnitude(a, w, b, {}, M, T * cin, cout), T * cin);
}

void check_conv(nn::Pool& pool, int64_t P, int64_t M, int64_t T, int64_t cin, int64_t cout, bool bias,
                double missing, uint32_t seed) {
    const auto nbr = random_table(M, T, P, missing, seed + 3);
    vk::CommandList cmd(pool.context());
    const auto rules = nn::ops::build_rulebook(cmd, pool, nn::upload_tensor(pool, nbr, {M, T}, DType::I32));
    cmd.submit_and_wait();
    check_conv(pool, rules, nbr, P, cin, cout, bias, seed);
}

void check_rulebook(nn::Pool& pool, const std::vector<int32_t>& nbr, int64_t M, int64_t T) {
    INFO("M=" << M << " T=" << T);
    vk::CommandList cmd(pool.context());
    const auto rules = nn::ops::build_rulebook(cmd, pool, nn::upload_tensor(pool, nbr, {M, T}, DType::I32));
    cmd.submit_and_wait();
    CHECK(rules.pairs.shape == std::vector<int64_t>{T, M, 2});
    CHECK(rules.counts.shape == std::vector<int64_t>{T});
    const auto want = ref::rulebook(nbr, M, T);
    const auto counts = nn::download_tensor<uint32_t>(pool.context(), rules.counts);
    const auto pairs = nn::download_tensor<uint32_t>(pool.context(), rules.pairs);
    for (int64_t t = 0; t < T; ++t) {
        INFO("tap " << t);
        REQUIRE(counts[size_t(t)] == want[size_t(t)].size());
        // The order within a tap is free: compare sorted.
        std::vector<std::pair<int32_t, int32_t>> got;
        for (uint32_t i = 0; i < counts[size_t(t)]; ++i) {
            const size_t at = 2 * (size_t(t * M) + i);
            got.push_back({int32_t(pairs[at]), int32_t(pairs[at + 1])});
        }
        std::sort(got.begin(), got.end());
        CHECK(got == want[size_t(t)]);
    }
}

}  // namespace

TEST_CASE("build_rulebook lists each tap's neighbours") {
    auto pool = nn::Pool::create(pg::test::gpu());
    check_rulebook(*pool, random_table(1, 27, 5, 0.5, 1), 1, 27);
    check_rulebook(*pool, random_table(700, 27, 900, 0.6, 2), 700, 27);  // several groups of 256 rows per tap
    check_rulebook(*pool, random_table(300, 125, 300, 0.8, 3), 300, 125);
    check_rulebook(*pool, random_table(513, 27, 513, 0.0, 4), 513, 27);  // every slot filled
    check_rulebook(*pool, random_table(50, 27, 0, 1.0, 5), 50, 27);      // no neighbours at all
    check_rulebook(*pool, {}, 0, 27);
    auto nbr = random_table(400, 27, 400, 0.3, 6);
    for (int64_t m = 0; m < 400; ++m) nbr[size_t(m * 27 + 5)] = -1;  // a tap without pairs
    check_rulebook(*pool, nbr, 400, 27);
}

// Variants: 32, 128 or 256 pairs per workgroup (by M) and depth chunks of 16 to 64 (by Cin).
TEST_CASE("sparse_conv over a rulebook matches CPU with lanes kernels") {
    auto pool = nn::Pool::create(pg::test::gpu());
    PathScope scope(GemmPath::Lanes, ConvPath::Auto);
    check_conv(*pool, 500, 400, 27, 32, 32, true, 0.6, 11);   // 128-pair groups
    check_conv(*pool, 300, 700, 27, 64, 40, false, 0.3, 12);  // 256-pair groups, a partial column tile
    check_conv(*pool, 60, 50, 27, 128, 64, true, 0.5, 13);    // 32-pair groups
    check_conv(*pool, 0, 7, 27, 64, 8, true, 1.0, 14);        // no points to gather: bias only
}

TEST_CASE("sparse_conv over a rulebook matches CPU with lanes kernels, 16-deep chunks and 5x5x5 taps") {
    auto pool = nn::Pool::create(pg::test::gpu());
    PathScope scope(GemmPath::Lanes, ConvPath::Auto);
    check_conv(*pool, 40, 1, 27, 16, 8, true, 0.5, 21);       // one row
    check_conv(*pool, 300, 257, 27, 48, 16, true, 0.4, 22);   // three chunks of 16 per tap
    check_conv(*pool, 100, 90, 27, 192, 24, false, 0.5, 23);  // three chunks of 64 per tap
    check_conv(*pool, 200, 150, 125, 16, 32, true, 0.85, 24);
}

// Past 4 M floats of taps x rows x channels the lanes kernels run a dispatch per tap, each
// adding into y, instead of all taps into slices at once.
TEST_CASE("sparse_conv over a rulebook matches CPU with lanes kernels, a dispatch per tap") {
    auto pool = nn::Pool::create(pg::test::gpu());
    PathScope scope(GemmPath::Lanes, ConvPath::Auto);
    check_conv(*pool, 2500, 2500, 27, 32, 64, true, 0.6, 81);   // 4.3 M: one dispatch per tap
    check_conv(*pool, 900, 1000, 125, 48, 40, false, 0.9, 82);  // 5 M, three chunks of 16 per tap
}

TEST_CASE("sparse_conv over a rulebook matches CPU with the tiled kernel") {
    auto pool = nn::Pool::create(pg::test::gpu());
    PathScope scope(GemmPath::Tiled, ConvPath::Rulebook);
    check_conv(*pool, 500, 400, 27, 32, 32, true, 0.6, 31);
    check_conv(*pool, 900, 700, 125, 2, 32, false, 0.8, 32);
    check_conv(*pool, 50, 1, 27, 8, 5, true, 0.5, 33);
    check_conv(*pool, 40, 130, 27, 3, 70, true, 0.0, 34);  // partial row and column tiles
    check_conv(*pool, 0, 7, 27, 32, 8, true, 1.0, 35);
}

TEST_CASE("sparse_conv reuses a rulebook of a submanifold table across convolutions") {
    auto pool = nn::Pool::create(pg::test::gpu());
    // Distinct random voxels in a 16^3 box: the neighbour map of a real sparse grid.
    std::mt19937 rng(41);
    std::vector<int32_t> grid;
    std::vector<bool> taken(16 * 16 * 16, false);
    while (grid.size() < 3 * 600) {
        const uint32_t c = rng() % (16 * 16 * 16);
        if (taken[c]) continue;
        taken[c] = true;
        grid.insert(grid.end(), {int32_t(c / 256), int32_t(c / 16 % 16), int32_t(c % 16)});
    }
    const int64_t M = 600;
    vk::CommandList cmd(pool->context());
    Tensor nbr = nn::ops::neighbor_map(cmd, *pool, nn::upload_tensor(*pool, grid, {M, 3}, DType::I32),
                                       nn::upload_tensor(*pool, std::vector<int32_t>(M, 0), {M}, DType::I32), 3);
    const auto rules = nn::ops::build_rulebook(cmd, *pool, nbr);
    cmd.submit_and_wait();
    const auto table = nn::download_tensor<int32_t>(pool->context(), nbr);
    for (GemmPath g : {GemmPath::Lanes, GemmPath::Tiled}) {
        PathScope scope(g, ConvPath::Rulebook);
        check_conv(*pool, rules, table, M, 32, 64, true, 51);
        check_conv(*pool, rules, table, M, 64, 32, false, 52);
    }
    // Either entry point gives the same bits (same sums in the same order).
    auto x = nn::upload_tensor(*pool, ref::random_uniform(size_t(M * 32), 53), {M, 32}, DType::F32);
    auto w = nn::upload_tensor(*pool, ref::random_uniform(size_t(32 * 27 * 32), 54), {32, 27 * 32}, DType::F32);
    Tensor y1 = nn::ops::sparse_conv(cmd, *pool, x, rules, w, {});
    Tensor y2 = nn::ops::sparse_conv(cmd, *pool, x, nbr, w, {});
    cmd.submit_and_wait();
    CHECK(nn::download_tensor<float>(pool->context(), y1) == nn::download_tensor<float>(pool->context(), y2));
}

TEST_CASE("sparse_conv keeps the gathered GEMM where the rulebook kernels do not fit or are not chosen") {
    auto pool = nn::Pool::create(pg::test::gpu());
    // (One shader variant for both: each test process compiles what it uses.)
    {
        PathScope scope(GemmPath::Lanes, ConvPath::Rulebook);
        check_conv(*pool, 300, 200, 27, 64, 36, true, 0.5, 61);  // Cout % 8 != 0: gathered, scalar y
    }
    PathScope scope(GemmPath::Lanes, ConvPath::Gathered);
    check_conv(*pool, 300, 200, 27, 64, 36, false, 0.5, 62);
}

TEST_CASE("sparse_conv's gathered lanes GEMM reads 8- and 24-channel rows in 8-column lookups") {
    // The A_SEG 8 variants (Cin % 8 == 0, not % 32; Cout % 8 == 0), on both row counts per
    // workgroup and both chunk depths, with missing neighbours; Cout 36 keeps the scalar kernels.
    auto pool = nn::Pool::create(pg::test::gpu());
    PathScope scope(GemmPath::Lanes, ConvPath::Gathered);
    check_conv(*pool, 300, 200, 27, 8, 8, true, 0.5, 71);     // 216 deep: chunks of 64, then 32
    check_conv(*pool, 60, 50, 27, 24, 16, false, 0.3, 72);    // 64 rows a workgroup, 648 deep
    check_conv(*pool, 900, 700, 125, 8, 16, true, 0.85, 73);  // the stem's 5x5x5 taps
    check_conv(*pool, 100, 90, 27, 8, 36, false, 0.5, 74);    // scalar y: per-column lookups
}

TEST_CASE("build_rulebook and sparse_conv over a rulebook reject bad shapes") {
    auto pool = nn::Pool::create(pg::test::gpu());
    vk::CommandList cmd(pool->context());
    CHECK_THROWS_AS(nn::ops::build_rulebook(cmd, *pool, pool->empty({6, 27})), std::invalid_argument);
    CHECK_THROWS_AS(nn::ops::build_rulebook(cmd, *pool, pool->empty({27}, DType::I32)), std::invalid_argument);
    Tensor nbr = pool->empty({6, 27}, DType::I32);
    cmd.fill(*nbr.buffer, 0xFFFFFFFFu);
    const auto rules = nn::ops::build_rulebook(cmd, *pool, nbr);
    Tensor x = pool->empty({10, 16}), w = pool->empty({8, 27 * 16});
    CHECK_THROWS_AS(nn::ops::sparse_conv(cmd, *pool, pool->empty({10, 8}), rules, w, {}), std::invalid_argument);
    CHECK_THROWS_AS(nn::ops::sparse_conv(cmd, *pool, x, rules, w, pool->empty({7})), std::invalid_argument);
    CHECK_THROWS_AS(nn::ops::sparse_conv(cmd, *pool, x, rules, pool->empty({8, 27 * 16}, DType::I32), {}),
                    std::invalid_argument);
    cmd.submit_and_wait();
}

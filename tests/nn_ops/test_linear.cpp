// nn.Linear and sparse convolution (nn/ops/linear.h) against the double CPU reference, on both
// kernel families: lanes (lavapipe's default) and tiled (GPUs' default).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "nn/ops/linear.h"
#include "tests/gpu_fixture.h"
#include "tests/reference/nn_dense_ref.h"

using namespace pg;
using nn::DType;
using nn::Tensor;
namespace ref = pg::test::ref;

namespace {

// Restores the automatic kernel choice when a test ends, also on failure.
struct PathScope {
    explicit PathScope(nn::ops::GemmPath p) { nn::ops::set_gemm_path(p); }
    ~PathScope() { nn::ops::set_gemm_path(nn::ops::GemmPath::Auto); }
};

// f32 sums drift with the magnitude of their terms; 3 ulps * sqrt(K) of it is a loose bound
// for the accumulation orders the kernels use, and far below any indexing mistake.
// A GELU after the sum scales errors by at most 1.13 and adds its own 1e-6 (1 + |y|).
void check_close(const std::vector<float>& got, const std::vector<double>& want, const std::vector<double>& mag,
                 int64_t K, bool gelu = false) {
    REQUIRE(got.size() == want.size());
    double worst = 0;
    size_t at = 0;
    for (size_t i = 0; i < got.size(); ++i) {
        double tol = 2e-7 * std::sqrt(double(K) + 1.0) * mag[i] + 1e-6;
        if (gelu) tol = 1.13 * tol + 1e-6 * (1.0 + std::fabs(want[i]));
        const double r = std::fabs(double(got[i]) - want[i]) / tol;
        if (!(r <= worst)) {
            worst = r;
            at = i;
        }
    }
    INFO("worst at " << at << ": got " << got[at] << ", want " << want[at] << " (error / tolerance " << worst << ")");
    CHECK(worst <= 1.0);
}

void check_linear(nn::Pool& pool, int64_t M, int64_t K, int64_t N, bool bias, bool residual, uint32_t seed,
                  bool gelu = false) {
    INFO("M=" << M << " K=" << K << " N=" << N << (bias ? " bias" : "") << (residual ? " residual" : "")
              << (gelu ? " gelu" : ""));
    auto x = ref::random_uniform(size_t(M * K), seed), w = ref::random_uniform(size_t(N * K), seed + 1);
    auto b = bias ? ref::random_uniform(size_t(N), seed + 2) : std::vector<float>{};
    auto r = residual ? ref::random_uniform(size_t(M * N), seed + 3, -4.0f, 4.0f) : std::vector<float>{};
    Tensor tx = nn::upload_tensor(pool, x, {M, K}, DType::F32), tw = nn::upload_tensor(pool, w, {N, K}, DType::F32);
    Tensor tb = bias ? nn::upload_tensor(pool, b, {N}, DType::F32) : Tensor{};
    Tensor tr = residual ? nn::upload_tensor(pool, r, {M, N}, DType::F32) : Tensor{};
    vk::CommandList cmd(pool.context());
    Tensor y = nn::ops::linear(cmd, pool, tx, tw, tb, tr, gelu ? nn::ops::Activation::Gelu : nn::ops::Activation::None);
    cmd.submit_and_wait();
    CHECK(y.shape == std::vector<int64_t>{M, N});
    auto want = ref::linear(x, w, b, r, M, K, N);
    if (gelu)
        for (double& v : want) v = ref::gelu(v);
    check_close(nn::download_tensor<float>(pool.context(), y), want, ref::linear_magnitude(x, w, b, r, M, K, N), K,
                gelu);
}

void check_conv(nn::Pool& pool, int64_t P, int64_t M, int64_t T, int64_t cin, int64_t cout, bool bias,
                double missing, uint32_t seed) {
    INFO("P=" << P << " M=" << M << " T=" << T << " Cin=" << cin << " Cout=" << cout << (bias ? " bias" : ""));
    auto x = ref::random_uniform(size_t(P * cin), seed), w = ref::random_uniform(size_t(cout * T * cin), seed + 1);
    auto b = bias ? ref::random_uniform(size_t(cout), seed + 2) : std::vector<float>{};
    std::mt19937 rng(seed + 3);
    std::vector<int32_t> nbr(size_t(M * T));
    for (auto& j : nbr)
        j = std::uniform_real_distribution<double>(0, 1)(rng) < missing ? -1
                                                                        : int32_t(rng() % uint32_t(std::max<int64_t>(P, 1)));
    if (P == 0) std::fill(nbr.begin(), nbr.end(), -1);
    Tensor tx = nn::upload_tensor(pool, x, {P, cin}, DType::F32);
    Tensor tw = nn::upload_tensor(pool, w, {cout, T * cin}, DType::F32);
    Tensor tn = nn::upload_tensor(pool, nbr, {M, T}, DType::I32);
    Tensor tb = bias ? nn::upload_tensor(pool, b, {cout}, DType::F32) : Tensor{};
    vk::CommandList cmd(pool.context());
    Tensor y = nn::ops::sparse_conv(cmd, pool, tx, tn, tw, tb);
    cmd.submit_and_wait();
    CHECK(y.shape == std::vector<int64_t>{M, cout});
    const auto a = ref::gather_conv_input(x, nbr, M, T, cin);
    check_close(nn::download_tensor<float>(pool.context(), y), ref::linear(a, w, b, {}, M, T * cin, cout),
                ref::linear_magnitude(a, w, b, {}, M, T * cin, cout), T * cin);
}

}  // namespace

// Lanes kernels come in variants (shaders/nn/linear_lanes_*); each test case below reaches a
// few of them, so no single case pays for compiling them all on lavapipe.
TEST_CASE("linear matches CPU on odd sizes with lanes kernels and scalar loads") {
    auto pool = nn::Pool::create(pg::test::gpu());
    PathScope scope(nn::ops::GemmPath::Lanes);
    check_linear(*pool, 1, 3, 5, true, false, 1);
    check_linear(*pool, 1, 1, 1, false, false, 2);
    check_linear(*pool, 1000, 77, 131, true, false, 3);
    check_linear(*pool, 65, 1, 64, true, true, 4);
    check_linear(*pool, 5, 1100, 3, true, false, 5);
}

TEST_CASE("linear matches CPU on 8-wide sizes with lanes kernels and 8-wide loads") {
    auto pool = nn::Pool::create(pg::test::gpu());
    PathScope scope(nn::ops::GemmPath::Lanes);
    check_linear(*pool, 3, 64, 8, false, true, 11);    // 64-row groups
    check_linear(*pool, 128, 96, 72, false, false, 12);  // chunks of 64 then 32
    check_linear(*pool, 129, 40, 33, true, true, 13);  // 256-row groups, scalar y
    check_linear(*pool, 300, 24, 16, true, false, 14);
    check_linear(*pool, 61, 3456, 72, true, true, 15);  // deep K, few rows
}

TEST_CASE("linear matches CPU on PTv3 shapes with bias and fused residual with lanes kernels") {
    auto pool = nn::Pool::create(pg::test::gpu());
    PathScope scope(nn::ops::GemmPath::Lanes);
    check_linear(*pool, 2048, 32, 96, true, false, 21);  // qkv at level 0
    check_linear(*pool, 2048, 128, 32, true, true, 22);  // fc2 with the residual
    check_linear(*pool, 700, 256, 64, false, true, 23);
    check_linear(*pool, 2048, 32, 128, true, false, 24, true);  // fc1 with GELU fused
}

TEST_CASE("linear applies GELU in the last chunk or after with lanes kernels") {
    auto pool = nn::Pool::create(pg::test::gpu());
    PathScope scope(nn::ops::GemmPath::Lanes);
    check_linear(*pool, 100, 96, 64, true, false, 25, true);  // fused in the 64-row, chunk-32 variant
    check_linear(*pool, 300, 40, 24, false, false, 26, true);
    check_linear(*pool, 7, 5, 3, true, false, 27, true);      // no fused variant: a separate pass
}

TEST_CASE("linear matches CPU on odd and PTv3 and split-K shapes with the tiled kernel") {
    auto pool = nn::Pool::create(pg::test::gpu());
    PathScope scope(nn::ops::GemmPath::Tiled);
    check_linear(*pool, 1, 3, 5, true, false, 31);
    check_linear(*pool, 1000, 77, 131, true, false, 32);
    check_linear(*pool, 129, 40, 33, true, true, 33);
    check_linear(*pool, 2048, 128, 32, true, true, 34);
    check_linear(*pool, 61, 3456, 72, true, true, 35);  // few tiles, deep K: split-K
    check_linear(*pool, 5, 1100, 3, true, false, 36);
    check_linear(*pool, 300, 40, 24, true, false, 37, true);
    check_linear(*pool, 61, 3456, 72, true, false, 38, true);  // GELU in the split-K epilogue
}

TEST_CASE("linear_deep sums a deep product in slices like the reference, on both kernel families") {
    // Weight gradients' shape: few rows and columns, thousands of depth. On the lanes path the
    // depth goes in slices of one chunk each, or of several when the partial sums' budget is
    // small, a short last slice, and falls back to linear() where the split kernels cannot.
    struct Case {
        int64_t M, K, N;
        uint64_t budget;
    };
    const Case cases[] = {{32, 4096, 32, uint64_t(1) << 24},  // 64 slices of one chunk
                          {24, 4104, 16, 24 * 16 * 5},        // 5 slices of 13 chunks, the last short
                          {300, 1000, 8, uint64_t(1) << 24},  // 256-row groups, depth not a multiple of 64
                          {7, 3000, 5, uint64_t(1) << 24}};   // odd sizes: linear()
    for (auto path : {nn::ops::GemmPath::Lanes, nn::ops::GemmPath::Tiled}) {
        PathScope scope(path);
        auto pool = nn::Pool::create(pg::test::gpu());
        uint32_t seed = 40;
        for (const Case& c : cases) {
            INFO("M=" << c.M << " K=" << c.K << " N=" << c.N << " budget " << c.budget
                      << (path == nn::ops::GemmPath::Lanes ? " lanes" : " tiled"));
            auto x = ref::random_uniform(size_t(c.M * c.K), seed), w = ref::random_uniform(size_t(c.N * c.K), seed + 1);
            seed += 2;
            Tensor tx = nn::upload_tensor(*pool, x, {c.M, c.K}, DType::F32), tw = nn::upload_tensor(*pool, w, {c.N, c.K}, DType::F32);
            vk::CommandList cmd(pool->context());
            Tensor y = nn::ops::linear_deep(cmd, *pool, tx, tw, c.budget);
            cmd.submit_and_wait();
            CHECK(y.shape == std::vector<int64_t>{c.M, c.N});
            check_close(nn::download_tensor<float>(pool->context(), y), ref::linear(x, w, {}, {}, c.M, c.K, c.N),
                        ref::linear_magnitude(x, w, {}, {}, c.M, c.K, c.N), c.K);
        }
    }
}

TEST_CASE("linear keeps a rank-1 input rank 1 and handles empty outputs") {
    auto pool = nn::Pool::create(pg::test::gpu());
    auto x = ref::random_uniform(16, 31), w = ref::random_uniform(48, 32);
    Tensor tx = nn::upload_tensor(*pool, x, {16}, DType::F32), tw = nn::upload_tensor(*pool, w, {3, 16}, DType::F32);
    vk::CommandList cmd(pool->context());
    Tensor y = nn::ops::linear(cmd, *pool, tx, tw, {});
    Tensor x0 = pool->empty({0, 16});
    Tensor y0 = nn::ops::linear(cmd, *pool, x0, tw, {});
    cmd.submit_and_wait();
    CHECK(y.shape == std::vector<int64_t>{3});
    CHECK(y0.shape == std::vector<int64_t>{0, 3});
    auto got = nn::download_tensor<float>(pool->context(), y);
    auto want = ref::linear(x, w, {}, {}, 1, 16, 3);
    for (size_t i = 0; i < 3; ++i) CHECK(std::fabs(got[i] - want[i]) < 1e-5);
}

TEST_CASE("linear rejects mismatched shapes and dtypes") {
    auto pool = nn::Pool::create(pg::test::gpu());
    vk::CommandList cmd(pool->context());
    Tensor x = pool->empty({4, 8}), w = pool->empty({5, 8}), bad_w = pool->empty({5, 7});
    CHECK_THROWS_AS(nn::ops::linear(cmd, *pool, x, bad_w, {}), std::invalid_argument);
    CHECK_THROWS_AS(nn::ops::linear(cmd, *pool, x, w, pool->empty({4})), std::invalid_argument);
    CHECK_THROWS_AS(nn::ops::linear(cmd, *pool, x, w, {}, pool->empty({5, 4})), std::invalid_argument);
    CHECK_THROWS_AS(nn::ops::linear(cmd, *pool, pool->empty({4, 8}, DType::I32), w, {}), std::invalid_argument);
    CHECK_THROWS_AS(nn::ops::linear(cmd, *pool, pool->empty({2, 4, 8}), w, {}), std::invalid_argument);
    CHECK_THROWS_AS(nn::ops::linear(cmd, *pool, x, w, {}, pool->empty({4, 5}), nn::ops::Activation::Gelu),
                    std::invalid_argument);
}

TEST_CASE("sparse_conv matches CPU for 3x3x3 kernels with missing neighbours with lanes kernels") {
    auto pool = nn::Pool::create(pg::test::gpu());
    PathScope scope(nn::ops::GemmPath::Lanes);
    check_conv(*pool, 500, 400, 27, 32, 32, true, 0.6, 41);   // 8-wide gathers, 2 taps per chunk
    check_conv(*pool, 300, 257, 27, 64, 40, false, 0.3, 42);  // 1 tap per chunk, scalar y
    check_conv(*pool, 60, 50, 27, 64, 64, true, 0.3, 43);     // 64-row groups
}

TEST_CASE("sparse_conv matches CPU for 5x5x5 kernels and odd channel counts with lanes kernels") {
    auto pool = nn::Pool::create(pg::test::gpu());
    PathScope scope(nn::ops::GemmPath::Lanes);
    check_conv(*pool, 900, 700, 125, 2, 32, false, 0.8, 51);  // the embedding: Cin 2
    check_conv(*pool, 50, 1, 27, 8, 5, true, 0.5, 52);        // Cin % 32 != 0: scalar gathers
    check_conv(*pool, 40, 33, 27, 3, 16, true, 0.0, 53);
    check_conv(*pool, 0, 7, 27, 32, 8, true, 1.0, 54);        // no points to gather: bias only
}

TEST_CASE("sparse_conv matches CPU with missing neighbours with the tiled kernel") {
    auto pool = nn::Pool::create(pg::test::gpu());
    PathScope scope(nn::ops::GemmPath::Tiled);
    check_conv(*pool, 500, 400, 27, 32, 32, true, 0.6, 61);
    check_conv(*pool, 900, 700, 125, 2, 32, false, 0.8, 62);
    check_conv(*pool, 50, 1, 27, 8, 5, true, 0.5, 63);
    check_conv(*pool, 40, 33, 27, 3, 16, true, 0.0, 64);
    check_conv(*pool, 0, 7, 27, 32, 8, true, 1.0, 65);
}

TEST_CASE("sparse_conv accepts the checkpoint's 5-D weight and rejects bad shapes") {
    auto pool = nn::Pool::create(pg::test::gpu());
    vk::CommandList cmd(pool->context());
    Tensor x = pool->empty({10, 4}), nbr = pool->empty({6, 27}, DType::I32);
    Tensor w5 = pool->empty({8, 3, 3, 3, 4});
    cmd.fill(*nbr.buffer, 0xFFFFFFFFu);  // all missing
    cmd.fill(*w5.buffer, 0x3F800000u);   // 1.0f
    Tensor y = nn::ops::sparse_conv(cmd, *pool, x, nbr, w5, {});
    cmd.submit_and_wait();
    CHECK(y.shape == std::vector<int64_t>{6, 8});
    for (float v : nn::download_tensor<float>(pool->context(), y)) CHECK(v == 0.0f);
    CHECK_THROWS_AS(nn::ops::sparse_conv(cmd, *pool, x, nbr, pool->empty({8, 27 * 5}), {}), std::invalid_argument);
    CHECK_THROWS_AS(nn::ops::sparse_conv(cmd, *pool, x, pool->empty({6, 27}), w5, {}), std::invalid_argument);
    CHECK_THROWS_AS(nn::ops::sparse_conv(cmd, *pool, x, nbr, w5, pool->empty({7})), std::invalid_argument);
}

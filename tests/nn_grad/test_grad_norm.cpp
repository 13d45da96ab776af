// LayerNorm and training-mode BatchNorm backward (nn/train/grad_ops.h), the training-mode
// BatchNorm forward with its running statistics: GPU == CPU reference, CPU reference == central
// finite differences, bit-identical reruns.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "nn/ops/linear.h"
#include "nn/train/grad_ops.h"
#include "nn/train/grad_reduce.h"
#include "shaders/nn/grad_shared.glsl"
#include "tests/gpu_fixture.h"
#include "tests/nn_grad/grad_test_util.h"
#include "tests/reference/nn_dense_ref.h"
#include "tests/reference/nn_grad_ref.h"

using namespace pg;
using nn::DType;
using nn::Tensor;
namespace ref = pg::test::ref;
namespace gref = pg::test::ref::grad;

using pg::test::down;
using pg::test::same_bits;
using pg::test::up;

namespace {




struct NormCase {
    std::vector<float> x, gamma, beta, dy;
};

NormCase norm_case(int64_t M, int64_t C, float offset, uint32_t seed) {
    return {ref::random_uniform(size_t(M * C), seed, offset - 2.0f, offset + 2.0f),
            ref::random_uniform(size_t(C), seed + 1, 0.5f, 1.5f), ref::random_uniform(size_t(C), seed + 2),
            ref::random_uniform(size_t(M * C), seed + 3)};
}

constexpr float kLnEps = 1e-5f, kBnEps = 1e-3f;

std::vector<std::vector<float>> gpu_layer_norm(nn::Pool& pool, const NormCase& c, int64_t M, int64_t C) {
    vk::CommandList cmd(pool.context());
    auto g = nn::grad::layer_norm_backward(cmd, pool, up(pool, c.x, {M, C}), up(pool, c.gamma, {C}), up(pool, c.dy, {M, C}),
                                           kLnEps);
    cmd.submit_and_wait();
    return {down(pool, g.dx), down(pool, g.dgamma), down(pool, g.dbeta)};
}

void check_layer_norm(nn::Pool& pool, int64_t M, int64_t C, float offset, uint32_t seed) {
    INFO("M=" << M << " C=" << C << " offset " << offset);
    const NormCase c = norm_case(M, C, offset, seed);
    const auto got = gpu_layer_norm(pool, c, M, C);
    const auto want = gref::layer_norm_backward(gref::to_double(c.x), gref::to_double(c.gamma), gref::to_double(c.dy), M,
                                                C, kLnEps);
    CHECK(gref::worst_error(got[0], want.dx, 1e-5) <= 1.0);
    CHECK(gref::worst_error_normwise(got[1], want.dgamma, 1e-5) <= 1.0);
    CHECK(gref::worst_error_normwise(got[2], want.dbeta, 1e-5) <= 1.0);
}

// Training forward (y, batch stats, running stats) and backward, GPU against CPU.
std::vector<std::vector<float>> gpu_batch_norm(nn::Pool& pool, const NormCase& c, int64_t M, int64_t C,
                                               const std::vector<float>& run_mean, const std::vector<float>& run_var) {
    // Every upload before recording: an upload acts at once and may reuse the buffer of a tensor
    // dropped while recording, which recorded work still reads.
    Tensor x = up(pool, c.x, {M, C}), gamma = up(pool, c.gamma, {C}), beta = up(pool, c.beta, {C});
    Tensor rm = up(pool, run_mean, {C}), rv = up(pool, run_var, {C}), dy = up(pool, c.dy, {M, C});
    vk::CommandList cmd(pool.context());
    auto f = nn::grad::batch_norm_train(cmd, pool, x, gamma, beta, rm, rv, kBnEps);
    auto g = nn::grad::batch_norm_backward(cmd, pool, x, f.mean, f.var, gamma, dy, kBnEps);
    cmd.submit_and_wait();
    CHECK(f.y.shape == x.shape);
    return {down(pool, f.y),  down(pool, f.mean),     down(pool, f.var),     down(pool, rm),
            down(pool, rv),   down(pool, g.dx),       down(pool, g.dgamma),  down(pool, g.dbeta)};
}

void check_batch_norm(nn::Pool& pool, int64_t M, int64_t C, float offset, uint32_t seed) {
    INFO("M=" << M << " C=" << C << " offset " << offset);
    const NormCase c = norm_case(M, C, offset, seed);
    const auto rm0 = ref::random_uniform(size_t(C), seed + 7), rv0 = ref::random_uniform(size_t(C), seed + 8, 0.5f, 2.0f);
    const auto got = gpu_batch_norm(pool, c, M, C, rm0, rv0);
    const auto x = gref::to_double(c.x), gamma = gref::to_double(c.gamma);
    const auto f = gref::batch_norm_train(x, gamma, gref::to_double(c.beta), M, C, kBnEps);
    auto rm = gref::to_double(rm0), rv = gref::to_double(rv0);
    gref::update_running_stats(rm, rv, f.mean, f.var, M, 0.01);
    const auto g = gref::batch_norm_backward(x, gamma, gref::to_double(c.dy), M, C, kBnEps);
    CHECK(gref::worst_error(got[0], f.y, 1e-5) <= 1.0);
    CHECK(gref::worst_error(got[1], f.mean, 1e-5) <= 1.0);
    CHECK(gref::worst_error(got[2], f.var, 1e-5) <= 1.0);
    CHECK(gref::worst_error(got[3], rm, 1e-5) <= 1.0);
    CHECK(gref::worst_error(got[4], rv, 1e-5) <= 1.0);
    CHECK(gref::worst_error(got[5], g.dx, 1e-5) <= 1.0);
    CHECK(gref::worst_error_normwise(got[6], g.dgamma, 1e-5) <= 1.0);
    CHECK(gref::worst_error_normwise(got[7], g.dbeta, 1e-5) <= 1.0);
}

}  // namespace

TEST_CASE("layer_norm backward matches the CPU reference") {
    auto pool = nn::Pool::create(pg::test::gpu());
    check_layer_norm(*pool, 1, 1, 0.0f, 1);
    check_layer_norm(*pool, 1, 8, 0.0f, 2);
    check_layer_norm(*pool, 5, 3, 0.0f, 3);
    check_layer_norm(*pool, 3, 77, 0.0f, 4);
    check_layer_norm(*pool, 129, 64, 100.0f, 5);  // far from zero: the two-pass statistics
    check_layer_norm(*pool, 8192, 64, 0.0f, 6);   // dgamma, dbeta sum 8192 rows
    check_layer_norm(*pool, 1000, 37, 3.0f, 7);
}

TEST_CASE("layer_norm backward reference matches finite differences") {
    const int64_t M = 3, C = 5;
    const NormCase c = norm_case(M, C, 0.5f, 11);
    const auto x = gref::to_double(c.x), gamma = gref::to_double(c.gamma), beta = gref::to_double(c.beta);
    const auto dy = gref::to_double(c.dy);
    const double eps = 1e-5;
    const auto g = gref::layer_norm_backward(x, gamma, dy, M, C, eps);
    auto loss = [&](const gref::Vec& xx, const gref::Vec& gg, const gref::Vec& bb) {
        return gref::dot(dy, gref::layer_norm_forward(xx, gg, bb, M, C, eps));
    };
    CHECK(gref::worst_error(g.dx, gref::numeric_gradient([&](const gref::Vec& v) { return loss(v, gamma, beta); }, x),
                            1e-6) <= 1);
    CHECK(gref::worst_error(g.dgamma, gref::numeric_gradient([&](const gref::Vec& v) { return loss(x, v, beta); }, gamma),
                            1e-6) <= 1);
    CHECK(gref::worst_error(g.dbeta, gref::numeric_gradient([&](const gref::Vec& v) { return loss(x, gamma, v); }, beta),
                            1e-6) <= 1);
}

TEST_CASE("layer_norm backward is bit-identical across runs") {
    auto pool = nn::Pool::create(pg::test::gpu());
    const NormCase c = norm_case(3000, 48, 1.0f, 21);
    const auto a = gpu_layer_norm(*pool, c, 3000, 48), b = gpu_layer_norm(*pool, c, 3000, 48);
    for (size_t i = 0; i < a.size(); ++i) CHECK(same_bits(a[i], b[i]));
}

TEST_CASE("batch_norm training forward with running stats and its backward match the CPU reference") {
    auto pool = nn::Pool::create(pg::test::gpu());
    check_batch_norm(*pool, 2, 1, 0.0f, 31);
    check_batch_norm(*pool, 5, 3, 0.0f, 32);
    check_batch_norm(*pool, 65, 9, 0.0f, 33);    // one row past a chunk
    check_batch_norm(*pool, 1000, 32, 10.0f, 34);
    check_batch_norm(*pool, 8192, 64, 0.0f, 35);
    check_batch_norm(*pool, 20000, 3, 5.0f, 36);  // chunks longer than 64 rows
}

TEST_CASE("batch_norm backward reference matches finite differences") {
    const int64_t M = 4, C = 3;
    const NormCase c = norm_case(M, C, 0.5f, 41);
    const auto x = gref::to_double(c.x), gamma = gref::to_double(c.gamma), beta = gref::to_double(c.beta);
    const auto dy = gref::to_double(c.dy);
    const double eps = 1e-3;
    const auto g = gref::batch_norm_backward(x, gamma, dy, M, C, eps);
    // The batch statistics move with x: the forward recomputes them at every probe.
    auto loss = [&](const gref::Vec& xx, const gref::Vec& gg, const gref::Vec& bb) {
        return gref::dot(dy, gref::batch_norm_train(xx, gg, bb, M, C, eps).y);
    };
    CHECK(gref::worst_error(g.dx, gref::numeric_gradient([&](const gref::Vec& v) { return loss(v, gamma, beta); }, x),
                            1e-6) <= 1);
    CHECK(gref::worst_error(g.dgamma, gref::numeric_gradient([&](const gref::Vec& v) { return loss(x, v, beta); }, gamma),
                            1e-6) <= 1);
    CHECK(gref::worst_error(g.dbeta, gref::numeric_gradient([&](const gref::Vec& v) { return loss(x, gamma, v); }, beta),
                            1e-6) <= 1);
}

TEST_CASE("batch_norm training is bit-identical across runs") {
    auto pool = nn::Pool::create(pg::test::gpu());
    const NormCase c = norm_case(5000, 32, 2.0f, 51);
    const std::vector<float> rm(32, 0.0f), rv(32, 1.0f);
    const auto a = gpu_batch_norm(*pool, c, 5000, 32, rm, rv), b = gpu_batch_norm(*pool, c, 5000, 32, rm, rv);
    for (size_t i = 0; i < a.size(); ++i) CHECK(same_bits(a[i], b[i]));
}

TEST_CASE("batch_norm training rejects a single row") {
    auto pool = nn::Pool::create(pg::test::gpu());
    vk::CommandList cmd(pool->context());
    Tensor x = up(*pool, {1.0f, 2.0f}, {1, 2}), v = up(*pool, {1.0f, 1.0f}, {2});
    CHECK_THROWS_AS(nn::grad::batch_norm_train(cmd, *pool, x, v, v, v, v, kBnEps), std::invalid_argument);
}

// CPU devices sum each column in one pass (nn/grad_column_sums), GPUs in chunk partials and
// their sum: the same float operations in the same order, so the same bits.
TEST_CASE("column sums: the one-pass kernel equals the two passes bit for bit, in every mode") {
    auto pool = nn::Pool::create(pg::test::gpu());
    struct Shape {
        int64_t rows, cols;
    };
    for (const Shape sh : {Shape{1, 1}, Shape{7, 3}, Shape{300, 17}, Shape{8192, 64}, Shape{20000, 9}})
        for (uint32_t mode : {PG_COLSUM_PLAIN, PG_COLSUM_SQDEV, PG_COLSUM_DEV, PG_COLSUM_ROWNORM}) {
            INFO("rows " << sh.rows << " cols " << sh.cols << " mode " << mode);
            const auto a = ref::random_uniform(size_t(sh.rows * sh.cols), 31 + mode, -2.0f, 3.0f);
            const auto b = ref::random_uniform(size_t(sh.rows * sh.cols), 37 + mode, -1.0f, 1.0f);
            const auto v = ref::random_uniform(size_t(std::max(sh.cols, 3 * sh.rows)), 41 + mode, 0.5f, 1.5f);
            const int64_t vn = int64_t(v.size());
            std::vector<float> got[2];
            for (int path = 0; path < 2; ++path) {
                nn::ops::set_gemm_path(path == 0 ? nn::ops::GemmPath::Lanes : nn::ops::GemmPath::Tiled);
                vk::CommandList cmd(pool->context());
                const Tensor ta = up(*pool, a, {sh.rows, sh.cols}), tb = up(*pool, b, {sh.rows, sh.cols}),
                             tv = up(*pool, v, {vn});
                const Tensor out = nn::grad::detail::column_sums(cmd, *pool, mode, ta, tb, tv, uint64_t(sh.rows),
                                                                 uint64_t(sh.cols), 0.25f);
                cmd.submit_and_wait();
                got[path] = down(*pool, out);
            }
            nn::ops::set_gemm_path(nn::ops::GemmPath::Auto);
            REQUIRE(got[0].size() == size_t(sh.cols));
            CHECK(same_bits(got[0], got[1]));
            // And the sums are right: the plain mode against a double sum.
            if (mode == PG_COLSUM_PLAIN)
                for (int64_t c = 0; c < sh.cols; ++c) {
                    double want = 0;
                    for (int64_t r = 0; r < sh.rows; ++r) want += a[size_t(r * sh.cols + c)];
                    CHECK(got[0][size_t(c)] == Approx(0.25 * want).margin(1e-3));
                }
        }
}

// LayerNorm and BatchNorm (nn/ops/norm.h) against the double CPU reference.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <vector>

#include "nn/ops/norm.h"
#include "tests/gpu_fixture.h"
#include "tests/reference/nn_dense_ref.h"

using namespace pg;
using nn::DType;
using nn::Tensor;
namespace ref = pg::test::ref;

namespace {

double worst_error(const std::vector<float>& got, const std::vector<double>& want, double rel) {
    REQUIRE(got.size() == want.size());
    double worst = 0;
    for (size_t i = 0; i < got.size(); ++i)
        worst = std::max(worst, std::fabs(double(got[i]) - want[i]) / (rel * (1.0 + std::fabs(want[i]))));
    return worst;
}

void check_layer_norm(nn::Pool& pool, int64_t M, int64_t C, float offset, uint32_t seed, bool residual = false) {
    INFO("M=" << M << " C=" << C << " offset " << offset << (residual ? " residual" : ""));
    // An offset far from zero makes a one-pass variance cancel; the two-pass one must not.
    auto x = ref::random_uniform(size_t(M * C), seed, offset - 2.0f, offset + 2.0f);
    auto g = ref::random_uniform(size_t(C), seed + 1, 0.5f, 1.5f), b = ref::random_uniform(size_t(C), seed + 2, -1.0f, 1.0f);
    Tensor tx = nn::upload_tensor(pool, x, {M, C}, DType::F32);
    Tensor tg = nn::upload_tensor(pool, g, {C}, DType::F32), tb = nn::upload_tensor(pool, b, {C}, DType::F32);
    vk::CommandList cmd(pool.context());
    auto r = residual ? ref::random_uniform(size_t(M * C), seed + 3, -3.0f, 3.0f) : std::vector<float>{};
    Tensor tr = residual ? nn::upload_tensor(pool, r, {M, C}, DType::F32) : Tensor{};
    Tensor y = nn::ops::layer_norm(cmd, pool, tx, tg, tb, 1e-5f, tr);
    cmd.submit_and_wait();
    CHECK(y.shape == tx.shape);
    auto want = ref::layer_norm(x, g, b, M, C, 1e-5);
    for (size_t i = 0; i < r.size(); ++i) want[i] += r[i];
    CHECK(worst_error(nn::download_tensor<float>(pool.context(), y), want, 1e-5) <= 1.0);
}

void check_batch_norm(nn::Pool& pool, int64_t M, int64_t C, bool gelu, uint32_t seed) {
    INFO("M=" << M << " C=" << C << (gelu ? " gelu" : ""));
    auto x = ref::random_uniform(size_t(M * C), seed, -3.0f, 3.0f);
    auto mean = ref::random_uniform(size_t(C), seed + 1, -1.0f, 1.0f), var = ref::random_uniform(size_t(C), seed + 2, 0.01f, 4.0f);
    auto g = ref::random_uniform(size_t(C), seed + 3, -2.0f, 2.0f), b = ref::random_uniform(size_t(C), seed + 4, -1.0f, 1.0f);
    auto up = [&](const std::vector<float>& v) { return nn::upload_tensor(pool, v, {C}, DType::F32); };
    Tensor tx = nn::upload_tensor(pool, x, {M, C}, DType::F32);
    vk::CommandList cmd(pool.context());
    Tensor y = nn::ops::batch_norm(cmd, pool, tx, up(mean), up(var), up(g), up(b), 1e-3f, gelu);
    cmd.submit_and_wait();
    CHECK(y.shape == tx.shape);
    CHECK(worst_error(nn::download_tensor<float>(pool.context(), y), ref::batch_norm(x, mean, var, g, b, M, C, 1e-3, gelu),
                      1e-5) <= 1.0);
}

}  // namespace

TEST_CASE("layer_norm matches CPU for odd and wide and offset rows") {
    auto pool = nn::Pool::create(pg::test::gpu());
    check_layer_norm(*pool, 1, 1, 0.0f, 1);
    check_layer_norm(*pool, 5, 3, 0.0f, 2);
    check_layer_norm(*pool, 3, 77, 0.0f, 3);
    check_layer_norm(*pool, 1000, 32, 0.0f, 4);
    check_layer_norm(*pool, 129, 64, 100.0f, 5);
    check_layer_norm(*pool, 40, 2048, 10.0f, 6);
    check_layer_norm(*pool, 17, 514, 0.0f, 7);
    check_layer_norm(*pool, 12, 36, 0.0f, 8);
}

TEST_CASE("layer_norm adds a fused residual") {
    auto pool = nn::Pool::create(pg::test::gpu());
    check_layer_norm(*pool, 300, 64, 0.0f, 21, true);
    check_layer_norm(*pool, 9, 13, 5.0f, 22, true);
}

TEST_CASE("batch_norm matches CPU with and without GELU") {
    auto pool = nn::Pool::create(pg::test::gpu());
    for (bool gelu : {false, true}) {
        check_batch_norm(*pool, 1, 1, gelu, 11);
        check_batch_norm(*pool, 9, 3, gelu, 12);
        check_batch_norm(*pool, 1000, 32, gelu, 13);
        check_batch_norm(*pool, 77, 512, gelu, 14);
        check_batch_norm(*pool, 13, 6, gelu, 15);
        check_batch_norm(*pool, 21, 12, gelu, 16);
    }
}

TEST_CASE("norms reject mismatched parameters") {
    auto pool = nn::Pool::create(pg::test::gpu());
    vk::CommandList cmd(pool->context());
    Tensor x = pool->empty({4, 8}), c8 = pool->empty({8}), c7 = pool->empty({7});
    CHECK_THROWS_AS(nn::ops::layer_norm(cmd, *pool, x, c7, c8, 1e-5f), std::invalid_argument);
    CHECK_THROWS_AS(nn::ops::layer_norm(cmd, *pool, pool->empty({4, 8}, DType::I32), c8, c8, 1e-5f),
                    std::invalid_argument);
    CHECK_THROWS_AS(nn::ops::batch_norm(cmd, *pool, x, c8, c8, c8, c7, 1e-3f), std::invalid_argument);
    CHECK_THROWS_AS(nn::ops::layer_norm(cmd, *pool, x, c8, c8, 1e-5f, pool->empty({8, 4})), std::invalid_argument);
}

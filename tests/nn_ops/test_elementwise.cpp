// erf/GELU, add, gather_rows and add_gathered (nn/ops/elementwise.h) against the CPU reference.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <vector>

#include "nn/ops/elementwise.h"
#include "tests/gpu_fixture.h"
#include "tests/reference/nn_dense_ref.h"

using namespace pg;
using nn::DType;
using nn::Tensor;
namespace ref = pg::test::ref;

namespace {

std::vector<int32_t> random_index(size_t n, int32_t bound, uint32_t seed) {
    std::mt19937 rng(seed);
    std::vector<int32_t> v(n);
    for (auto& i : v) i = int32_t(rng() % uint32_t(bound));
    return v;
}

// x over [-10, 10] on a fine grid (plus the exact ends and the piece boundary).
std::vector<float> erf_grid() {
    std::vector<float> v;
    for (int i = -400000; i <= 400000; ++i) v.push_back(float(i) * 2.5e-5f);
    for (float x : {0.875f, -0.875f, std::nextafter(0.875f, 0.0f), 1e-30f, -1e-30f}) v.push_back(x);
    return v;
}

}  // namespace

TEST_CASE("erf is within 2e-7 of std::erf from -10 to 10") {
    auto pool = nn::Pool::create(pg::test::gpu());
    const auto x = erf_grid();
    Tensor tx = nn::upload_tensor(*pool, x, {int64_t(x.size())}, DType::F32);
    vk::CommandList cmd(pool->context());
    Tensor y = nn::ops::erf(cmd, *pool, tx);
    cmd.submit_and_wait();
    const auto got = nn::download_tensor<float>(pool->context(), y);
    double worst = 0;
    float at = 0;
    for (size_t i = 0; i < x.size(); ++i) {
        const double e = std::fabs(double(got[i]) - std::erf(double(x[i])));
        if (!(e <= worst)) worst = e, at = x[i];
    }
    INFO("worst " << worst << " at x = " << at);
    CHECK(worst <= 2e-7);
}

TEST_CASE("gelu is the exact erf form to 1e-6 on vectors of any length") {
    auto pool = nn::Pool::create(pg::test::gpu());
    for (size_t extra : {0, 1, 3}) {  // 4-wide and scalar paths
        auto x = erf_grid();
        x.resize(x.size() - 5 + extra);
        Tensor tx = nn::upload_tensor(*pool, x, {int64_t(x.size())}, DType::F32);
        vk::CommandList cmd(pool->context());
        Tensor y = nn::ops::gelu(cmd, *pool, tx);
        cmd.submit_and_wait();
        const auto got = nn::download_tensor<float>(pool->context(), y);
        double worst = 0;
        for (size_t i = 0; i < x.size(); ++i) {
            const double want = ref::gelu(x[i]);
            worst = std::max(worst, std::fabs(got[i] - want) / (1e-6 * (1.0 + std::fabs(want))));
        }
        INFO("n = " << x.size());
        CHECK(worst <= 1.0);
    }
}

TEST_CASE("add matches CPU and rejects different shapes") {
    auto pool = nn::Pool::create(pg::test::gpu());
    for (std::vector<int64_t> shape : {std::vector<int64_t>{1}, {5, 3}, {1000, 64}, {7}}) {
        const size_t n = size_t(shape.size() == 1 ? shape[0] : shape[0] * shape[1]);
        auto a = ref::random_uniform(n, 1, -5.0f, 5.0f), b = ref::random_uniform(n, 2, -5.0f, 5.0f);
        Tensor ta = nn::upload_tensor(*pool, a, shape, DType::F32), tb = nn::upload_tensor(*pool, b, shape, DType::F32);
        vk::CommandList cmd(pool->context());
        Tensor y = nn::ops::add(cmd, *pool, ta, tb);
        cmd.submit_and_wait();
        CHECK(y.shape == shape);
        const auto got = nn::download_tensor<float>(pool->context(), y);
        size_t wrong = 0;
        for (size_t i = 0; i < n; ++i) wrong += got[i] != a[i] + b[i];
        CHECK(wrong == 0);
    }
    vk::CommandList cmd(pool->context());
    CHECK_THROWS_AS(nn::ops::add(cmd, *pool, pool->empty({4, 2}), pool->empty({2, 4})), std::invalid_argument);
}

TEST_CASE("gather_rows copies rows of any dtype") {
    auto pool = nn::Pool::create(pg::test::gpu());
    struct Case {
        std::vector<int64_t> shape;
        DType dtype;
        int64_t words;  // 32-bit words per row
    };
    for (const Case& c : {Case{{300}, DType::I32, 1}, Case{{300}, DType::U64, 2}, Case{{300, 3}, DType::F32, 3},
                          Case{{300, 64}, DType::F32, 64}, Case{{300, 4}, DType::U32, 4}, Case{{300, 2}, DType::U64, 4}}) {
        INFO("rank " << c.shape.size() << " " << nn::dtype_name(c.dtype));
        std::mt19937 rng(7);
        std::vector<uint32_t> x(size_t(300 * c.words));
        for (auto& v : x) v = rng();
        const auto idx = random_index(1001, 300, 8);
        Tensor tx = nn::upload_tensor(*pool, x.data(), c.shape, c.dtype);
        Tensor ti = nn::upload_tensor(*pool, idx, {int64_t(idx.size())}, DType::I32);
        vk::CommandList cmd(pool->context());
        Tensor y = nn::ops::gather_rows(cmd, *pool, tx, ti);
        cmd.submit_and_wait();
        auto want_shape = c.shape;
        want_shape[0] = int64_t(idx.size());
        CHECK(y.shape == want_shape);
        CHECK(y.dtype == c.dtype);
        CHECK(nn::download_tensor<uint32_t>(pool->context(), y) == ref::gather_rows(x, idx, c.words));
    }
    vk::CommandList cmd(pool->context());
    CHECK_THROWS_AS(nn::ops::gather_rows(cmd, *pool, pool->empty({4, 2}), pool->empty({3}, DType::U32)),
                    std::invalid_argument);
}

TEST_CASE("add_gathered matches CPU") {
    auto pool = nn::Pool::create(pg::test::gpu());
    for (int64_t C : {1, 3, 64}) {
        INFO("C = " << C);
        const int64_t P = 200, R = 777;
        auto a = ref::random_uniform(size_t(R * C), 1, -3.0f, 3.0f), x = ref::random_uniform(size_t(P * C), 2, -3.0f, 3.0f);
        const auto idx = random_index(size_t(R), int32_t(P), 3);
        Tensor ta = nn::upload_tensor(*pool, a, {R, C}, DType::F32), tx = nn::upload_tensor(*pool, x, {P, C}, DType::F32);
        Tensor ti = nn::upload_tensor(*pool, idx, {R}, DType::I32);
        vk::CommandList cmd(pool->context());
        Tensor y = nn::ops::add_gathered(cmd, *pool, ta, tx, ti);
        cmd.submit_and_wait();
        CHECK(y.shape == std::vector<int64_t>{R, C});
        const auto got = nn::download_tensor<float>(pool->context(), y);
        const auto want = ref::add_gathered(a, x, idx, C);
        size_t wrong = 0;
        for (size_t i = 0; i < got.size(); ++i) wrong += got[i] != float(want[i]);
        CHECK(wrong == 0);
    }
    vk::CommandList cmd(pool->context());
    CHECK_THROWS_AS(nn::ops::add_gathered(cmd, *pool, pool->empty({4, 2}), pool->empty({5, 3}), pool->empty({4}, DType::I32)),
                    std::invalid_argument);
}

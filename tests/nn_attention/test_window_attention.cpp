#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <random>
#include <stdexcept>
#include <vector>

#include "engine/vk/commands.h"
#include "nn/ops/attention.h"
#include "nn/tensor.h"
#include "tests/gpu_fixture.h"
#include "tests/reference/nn_attention_ref.h"

using namespace pg;

namespace {

struct Problem {
    std::vector<float> qkv;  // [N, 3C]
    std::vector<int32_t> order;
    std::vector<int32_t> offsets;
    int heads = 1, patch = 1;
    int channels = 0;
    double scale = 0;
    float magnitude = 1;  // bound of the q, k, v entries
};

// Clouds of the given sizes, q/k/v uniform in [-magnitude, magnitude], a random permutation
// as the serialized order (identity when `shuffle` is false).
Problem make_problem(const std::vector<int>& sizes, int heads, int head_dim, int patch, float magnitude,
                     uint64_t seed, bool shuffle = true) {
    Problem p;
    p.heads = heads;
    p.patch = patch;
    p.channels = heads * head_dim;
    p.scale = 1.0 / std::sqrt(double(head_dim));
    p.magnitude = magnitude;
    p.offsets = {0};
    for (int s : sizes) p.offsets.push_back(p.offsets.back() + s);
    const size_t n = size_t(p.offsets.back());
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(-magnitude, magnitude);
    p.qkv.resize(n * 3 * size_t(p.channels));
    for (float& x : p.qkv) x = u(rng);
    p.order.resize(n);
    std::iota(p.order.begin(), p.order.end(), 0);
    if (shuffle) std::shuffle(p.order.begin(), p.order.end(), rng);
    return p;
}

using nn::ops::AttentionKernel;

std::vector<float> run_gpu(const Problem& p, AttentionKernel kernel) {
    auto& ctx = test::gpu();
    auto pool = nn::Pool::create(ctx);
    const int64_t n = int64_t(p.order.size());
    nn::Tensor qkv = nn::upload_tensor(*pool, p.qkv, {n, 3 * int64_t(p.channels)}, nn::DType::F32);
    nn::Tensor order = nn::upload_tensor(*pool, p.order, {n}, nn::DType::I32);
    nn::Tensor offsets = nn::upload_tensor(*pool, p.offsets, {int64_t(p.offsets.size())}, nn::DType::I32);
    vk::CommandList cmd(ctx);
    nn::Tensor out =
        nn::ops::window_attention(cmd, *pool, qkv, order, offsets, p.heads, p.patch, float(p.scale), kernel);
    cmd.submit_and_wait();
    REQUIRE(out.shape == std::vector<int64_t>{n, int64_t(p.channels)});
    return nn::download_tensor<float>(ctx, out);
}

// Largest |gpu - ref| relative to the value range. fp32 logits carry a rounding error that
// grows with their magnitude, which the softmax passes on; the tolerance follows it.
const char* kernel_name(AttentionKernel k) {
    return k == AttentionKernel::Gpu ? "gpu" : k == AttentionKernel::Cpu ? "cpu" : "auto";
}

void check_against(const Problem& p, const std::vector<float>& got, const std::vector<double>& want) {
    REQUIRE(got.size() == want.size());
    const double max_logit = double(p.magnitude) * p.magnitude * (p.channels / p.heads) * p.scale;
    const double tol = 1e-5 + 4e-7 * max_logit;
    double worst = 0;
    size_t at = 0;
    for (size_t i = 0; i < got.size(); ++i) {
        const double e = std::isfinite(got[i]) ? std::abs(double(got[i]) - want[i]) / p.magnitude : INFINITY;
        if (e > worst) worst = e, at = i;
    }
    INFO("N = " << p.order.size() << ", clouds = " << p.offsets.size() - 1 << ", C = " << p.channels
                << ", heads = " << p.heads << ", patch = " << p.patch << "; worst at point " << at / p.channels
                << " channel " << at % p.channels << ": got " << got[at] << ", want " << want[at]);
    CHECK(worst <= tol);
}

// Both kernel variants (each tuned for one kind of device) against the reference.
void check(const Problem& p) {
    const auto want = test::ref::window_attention(p.qkv, p.order, p.offsets, p.heads, p.patch, p.scale);
    for (AttentionKernel k : {AttentionKernel::Gpu, AttentionKernel::Cpu}) {
        INFO("kernel " << kernel_name(k));
        check_against(p, run_gpu(p, k), want);
    }
}

}  // namespace

TEST_CASE("window attention: one cloud larger than the patch, with and without a partial last window") {
    check(make_problem({2500}, 2, 16, 1024, 1.0f, 1));  // 2500 % 1024 != 0: the last window is pulled back
    check(make_problem({2048}, 2, 16, 1024, 1.0f, 2));  // whole windows only
    check(make_problem({1000}, 2, 16, 256, 1.0f, 3, false));
    check(make_problem({1000}, 1, 16, 200, 1.0f, 4));  // windows not multiples of the query block
}

TEST_CASE("window attention: clouds no larger than the patch attend to themselves") {
    check(make_problem({300}, 2, 16, 1024, 1.0f, 5));
    check(make_problem({64}, 2, 16, 64, 1.0f, 6));
    check(make_problem({65}, 2, 16, 64, 1.0f, 7));
    check(make_problem({1}, 2, 16, 1024, 1.0f, 8));
    check(make_problem({2}, 4, 16, 1, 1.0f, 9));  // patch 1: every point attends to itself alone
}

TEST_CASE("window attention: several clouds of different sizes never mix") {
    check(make_problem({1, 37, 1500, 64, 700, 2049, 5}, 2, 16, 512, 1.0f, 10));
    check(make_problem({130, 1, 1, 2, 900, 33}, 4, 16, 128, 1.0f, 11));
    check(make_problem({3, 100, 77}, 1, 16, 7, 1.0f, 12));  // small windows, several per query block
    check(make_problem({40, 0, 300, 0}, 2, 16, 64, 1.0f, 15));  // empty clouds
    std::vector<int> many(300);
    std::mt19937 rng(13);
    for (int& s : many) s = 1 + int(rng() % 40);
    check(make_problem(many, 2, 16, 16, 1.0f, 14));
}

// One test per head size: each compiles its own pair of kernels, which is most of its time.
TEST_CASE("window attention: 1, 4 and 16 heads of size 16") {
    check(make_problem({700}, 1, 16, 256, 1.0f, 20));
    check(make_problem({700}, 4, 16, 256, 1.0f, 21));
    check(make_problem({700}, 16, 16, 256, 1.0f, 22));
}

TEST_CASE("window attention: heads of size 32") {
    check(make_problem({700}, 2, 32, 256, 1.0f, 23));
    check(make_problem({300, 41}, 3, 32, 128, 1.0f, 26));
}

TEST_CASE("window attention: heads of size 8") {
    check(make_problem({700}, 4, 8, 256, 1.0f, 24));
    check(make_problem({129}, 1, 8, 1024, 1.0f, 27));
}

TEST_CASE("window attention: heads of size 64") {
    check(make_problem({700}, 2, 64, 256, 1.0f, 25));
    check(make_problem({65, 3}, 1, 64, 50, 1.0f, 28));
}

TEST_CASE("window attention: large logits stay finite and accurate") {
    // Logits up to 16 * 4^2 / 4 = 64 and 16 * 12^2 / 4 = 576: exp overflows fp32 past 88.
    check(make_problem({1500, 200}, 2, 16, 512, 4.0f, 30));
    check(make_problem({1500, 200}, 2, 16, 512, 12.0f, 31));
    // One key dominates each window by far: the output is (nearly) its value.
    Problem p = make_problem({600}, 1, 16, 256, 1.0f, 32);
    for (size_t i = 0; i < p.order.size(); i += 97)
        for (int d = 0; d < 16; ++d) p.qkv[i * 48 + 16 + size_t(d)] *= 1000.0f;
    const auto want = test::ref::window_attention(p.qkv, p.order, p.offsets, p.heads, p.patch, p.scale);
    for (AttentionKernel k : {AttentionKernel::Gpu, AttentionKernel::Cpu}) {
        INFO("kernel " << kernel_name(k));
        const std::vector<float> got = run_gpu(p, k);
        double worst = 0;
        for (size_t i = 0; i < got.size(); ++i)
            worst = std::max(worst, std::isfinite(got[i]) ? std::abs(double(got[i]) - want[i]) : INFINITY);
        // Logits up to ~4000: fp32 rounding of the logits alone is ~1e-3 of them.
        CHECK(worst <= 2e-3);
    }
}

TEST_CASE("window attention: the output does not depend on leftovers in pooled buffers") {
    auto& ctx = test::gpu();
    auto pool = nn::Pool::create(ctx);
    Problem p = make_problem({90, 10}, 2, 16, 64, 1.0f, 40);
    const int64_t n = 100;
    // A NaN-filled buffer returned to the pool first: the output must overwrite every entry.
    {
        nn::Tensor junk = pool->empty({n, 32});
        std::vector<float> nan(size_t(n) * 32, NAN);
        vk::upload(ctx, *junk.buffer, nan.data(), nan.size() * 4);
    }
    nn::Tensor qkv = nn::upload_tensor(*pool, p.qkv, {n, 96}, nn::DType::F32);
    nn::Tensor order = nn::upload_tensor(*pool, p.order, {n}, nn::DType::I32);
    nn::Tensor offsets = nn::upload_tensor(*pool, p.offsets, {3}, nn::DType::I32);
    vk::CommandList cmd(ctx);
    nn::Tensor out = nn::ops::window_attention(cmd, *pool, qkv, order, offsets, 2, 64, float(p.scale));
    cmd.submit_and_wait();
    check_against(p, nn::download_tensor<float>(ctx, out),
                  test::ref::window_attention(p.qkv, p.order, p.offsets, 2, 64, p.scale));
}

TEST_CASE("window attention: shape errors are clear") {
    auto& ctx = test::gpu();
    auto pool = nn::Pool::create(ctx);
    vk::CommandList cmd(ctx);
    nn::Tensor qkv = pool->empty({10, 96});
    nn::Tensor order = pool->empty({10}, nn::DType::I32);
    nn::Tensor offsets = pool->empty({2}, nn::DType::I32);
    using nn::ops::window_attention;
    CHECK_THROWS_AS(window_attention(cmd, *pool, pool->empty({10, 95}), order, offsets, 2, 16, 0.25f),
                    std::invalid_argument);
    CHECK_THROWS_AS(window_attention(cmd, *pool, qkv, order, offsets, 3, 16, 0.25f), std::invalid_argument);
    CHECK_THROWS_AS(window_attention(cmd, *pool, qkv, order, offsets, 8, 16, 0.25f), std::invalid_argument);  // D = 4
    CHECK_THROWS_AS(window_attention(cmd, *pool, qkv, pool->empty({9}, nn::DType::I32), offsets, 2, 16, 0.25f),
                    std::invalid_argument);
    CHECK_THROWS_AS(window_attention(cmd, *pool, qkv, pool->empty({10}, nn::DType::F32), offsets, 2, 16, 0.25f),
                    std::invalid_argument);
    CHECK_THROWS_AS(window_attention(cmd, *pool, qkv, order, pool->empty({1}, nn::DType::I32), 2, 16, 0.25f),
                    std::invalid_argument);
    CHECK_THROWS_AS(window_attention(cmd, *pool, qkv, order, offsets, 2, 0, 0.25f), std::invalid_argument);
    CHECK_THROWS_WITH(window_attention(cmd, *pool, qkv, order, offsets, 3, 16, 0.25f),
                      Catch::Contains("32 channels do not split into 3 heads"));
}

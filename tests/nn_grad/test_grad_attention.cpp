// Backward of the serialized window attention (nn/train/grad_attention.h): the CPU reference
// against central finite differences of the CPU forward, the GPU against the CPU reference,
// bit-identical reruns, and a PTv3-sized run.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <random>
#include <stdexcept>
#include <vector>

#include "engine/vk/commands.h"
#include "nn/ops/attention.h"
#include "nn/train/grad_attention.h"
#include "tests/gpu_fixture.h"
#include "tests/reference/nn_attention_ref.h"
#include "tests/reference/nn_dense_ref.h"
#include "tests/reference/nn_grad_attention_ref.h"
#include "tests/reference/nn_grad_ref.h"

using namespace pg;
using nn::DType;
using nn::Tensor;
namespace ref = pg::test::ref;
namespace gref = pg::test::ref::grad;

namespace {

// Clouds of the given sizes, a random serialization order, random qkv and dout.
struct Case {
    std::vector<int32_t> order, offsets;
    std::vector<float> qkv, dout;
    int64_t n = 0, channels = 0;
    int heads = 1, patch = 1;
    float scale = 1.0f;
};

Case make_case(const std::vector<int32_t>& clouds, int heads, int head_dim, int patch, uint32_t seed) {
    Case c;
    c.offsets = {0};
    for (int32_t size : clouds) c.offsets.push_back(c.offsets.back() + size);
    c.n = c.offsets.back();
    c.channels = int64_t(heads) * head_dim;
    c.heads = heads;
    c.patch = patch;
    c.scale = 1.5f / std::sqrt(float(head_dim));  // logits of a few units: a peaked but not saturated softmax
    c.order.resize(size_t(c.n));
    std::iota(c.order.begin(), c.order.end(), 0);
    std::shuffle(c.order.begin(), c.order.end(), std::mt19937(seed));
    c.qkv = ref::random_uniform(size_t(c.n * 3 * c.channels), seed + 1);
    c.dout = ref::random_uniform(size_t(c.n * c.channels), seed + 2);
    return c;
}

std::vector<float> gpu_backward(nn::Pool& pool, const Case& c,
                                nn::ops::AttentionKernel kernel = nn::ops::AttentionKernel::Auto) {
    Tensor qkv = nn::upload_tensor(pool, c.qkv, {c.n, 3 * c.channels}, DType::F32);
    Tensor order = nn::upload_tensor(pool, c.order, {c.n}, DType::I32);
    Tensor offsets = nn::upload_tensor(pool, c.offsets, {int64_t(c.offsets.size())}, DType::I32);
    Tensor dout = nn::upload_tensor(pool, c.dout, {c.n, c.channels}, DType::F32);
    vk::CommandList cmd(pool.context());
    Tensor dqkv = nn::grad::window_attention_backward(cmd, pool, qkv, order, offsets, c.heads, c.patch, c.scale, dout,
                                                     kernel);
    cmd.submit_and_wait();
    CHECK(dqkv.shape == std::vector<int64_t>{c.n, 3 * c.channels});
    return nn::download_tensor<float>(pool.context(), dqkv);
}

gref::Vec ref_backward(const Case& c) {
    return gref::window_attention_backward(gref::to_double(c.qkv), c.order, c.offsets, c.heads, c.patch, c.scale,
                                           gref::to_double(c.dout));
}

}  // namespace

TEST_CASE("window attention backward: CPU reference matches finite differences") {
    struct Shape {
        std::vector<int32_t> clouds;
        int heads, head_dim, patch;
        size_t samples;  // entries of qkv to difference; 0: all of them
    };
    // n < K, n == K, n % K != 0 (a pulled-back last window), one point, several clouds.
    const Shape shapes[] = {{{5, 16, 23, 1}, 1, 8, 8, 0},
                            {{3, 40, 17}, 2, 8, 16, 0},
                            {{100, 37, 163}, 2, 16, 32, 400}};
    uint32_t seed = 10;
    for (const Shape& s : shapes) {
        const Case c = make_case(s.clouds, s.heads, s.head_dim, s.patch, seed += 10);
        INFO("N=" << c.n << " H=" << s.heads << " D=" << s.head_dim << " K=" << s.patch);
        const gref::Vec qkv = gref::to_double(c.qkv), dout = gref::to_double(c.dout);
        // The double forward is the one the tests of the forward trust.
        CHECK(gref::worst_error(gref::window_attention_forward(qkv, c.order, c.offsets, c.heads, c.patch, c.scale),
                                ref::window_attention(c.qkv, c.order, c.offsets, c.heads, c.patch, c.scale),
                                1e-12) <= 1.0);
        const gref::Vec want = ref_backward(c);
        auto loss = [&](const gref::Vec& x) {
            return gref::dot(dout, gref::window_attention_forward(x, c.order, c.offsets, c.heads, c.patch, c.scale));
        };
        std::vector<size_t> entries(qkv.size());
        std::iota(entries.begin(), entries.end(), size_t(0));
        if (s.samples) {
            std::shuffle(entries.begin(), entries.end(), std::mt19937(seed));
            entries.resize(s.samples);
        }
        const double eps = 1e-5;
        double worst = 0;
        gref::Vec x = qkv;
        for (size_t i : entries) {
            x[i] = qkv[i] + eps;
            const double up = loss(x);
            x[i] = qkv[i] - eps;
            const double down = loss(x);
            x[i] = qkv[i];
            const double num = (up - down) / (2 * eps);
            worst = std::max(worst, std::fabs(num - want[i]) / (1e-7 * (1 + std::fabs(num))));
        }
        CHECK(worst <= 1.0);
    }
}

const char* kernel_name(nn::ops::AttentionKernel k) { return k == nn::ops::AttentionKernel::Cpu ? "cpu" : "gpu"; }
constexpr nn::ops::AttentionKernel kKernels[] = {nn::ops::AttentionKernel::Gpu, nn::ops::AttentionKernel::Cpu};

TEST_CASE("window attention backward: GPU matches the CPU reference, both kernels") {
    auto pool = nn::Pool::create(pg::test::gpu());
    struct Shape {
        std::vector<int32_t> clouds;
        int heads, head_dim, patch;
    };
    const Shape shapes[] = {
        {{1}, 1, 8, 16},                        // one point
        {{7}, 2, 8, 16},                        // one cloud smaller than a window
        {{1, 7, 16, 17, 64, 65, 100}, 1, 16, 16},  // n < K, n == K, n = K + 1, exact multiples, a remainder
        {{300, 1, 45}, 2, 16, 48},              // a window size that is no multiple of the workgroup
        {{130, 33}, 1, 32, 32},
        {{90, 20}, 2, 64, 24},
        {{2000, 1100}, 2, 16, 1024},            // PTv3's patch: n < K and a pulled-back window
        {{200, 48, 49, 5, 97}, 2, 8, 48},       // the tiny config's head and patch: blocks of part of a window
    };
    uint32_t seed = 100;
    for (const Shape& s : shapes) {
        const Case c = make_case(s.clouds, s.heads, s.head_dim, s.patch, seed += 10);
        INFO("N=" << c.n << " H=" << s.heads << " D=" << s.head_dim << " K=" << s.patch);
        const gref::Vec want = ref_backward(c);
        for (nn::ops::AttentionKernel k : kKernels) {
            INFO("kernel " << kernel_name(k));
            // Per element: |got - want| <= 1e-5 * (1 + |want|).
            CHECK(gref::worst_error(gpu_backward(*pool, c, k), want, 1e-5) <= 1.0);
        }
    }
}

TEST_CASE("window attention backward: reruns are bit-identical") {
    auto pool = nn::Pool::create(pg::test::gpu());
    const Case c = make_case({700, 301, 5}, 2, 16, 128, 7);
    for (nn::ops::AttentionKernel k : kKernels) {
        INFO("kernel " << kernel_name(k));
        const auto a = gpu_backward(*pool, c, k), b = gpu_backward(*pool, c, k);
        REQUIRE(a.size() == b.size());
        CHECK(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0);
    }
}

TEST_CASE("window attention backward: PTv3 size runs (N=8192 C=32 H=2 K=1024)") {
    auto pool = nn::Pool::create(pg::test::gpu());
    const Case c = make_case({5000, 3192}, 2, 16, 1024, 3);
    const auto g = gpu_backward(*pool, c);
    CHECK(std::all_of(g.begin(), g.end(), [](float v) { return std::isfinite(v); }));
}

TEST_CASE("window attention backward: rejects bad shapes") {
    auto pool = nn::Pool::create(pg::test::gpu());
    const Case c = make_case({10}, 2, 8, 4, 1);
    Tensor qkv = nn::upload_tensor(*pool, c.qkv, {c.n, 3 * c.channels}, DType::F32);
    Tensor order = nn::upload_tensor(*pool, c.order, {c.n}, DType::I32);
    Tensor offsets = nn::upload_tensor(*pool, c.offsets, {int64_t(c.offsets.size())}, DType::I32);
    Tensor dout = nn::upload_tensor(*pool, c.dout, {c.n, c.channels}, DType::F32);
    Tensor short_dout = pool->empty({c.n, c.channels / 2}, DType::F32);
    vk::CommandList cmd(pool->context());
    using nn::grad::window_attention_backward;
    CHECK_THROWS_AS(window_attention_backward(cmd, *pool, qkv, order, offsets, 2, 4, c.scale, short_dout),
                    std::invalid_argument);
    CHECK_THROWS_AS(window_attention_backward(cmd, *pool, qkv, order, offsets, 3, 4, c.scale, dout),
                    std::invalid_argument);
    CHECK_THROWS_AS(window_attention_backward(cmd, *pool, qkv, order, offsets, 2, 0, c.scale, dout),
                    std::invalid_argument);
    CHECK_THROWS_AS(window_attention_backward(cmd, *pool, qkv, offsets, offsets, 2, 4, c.scale, dout),
                    std::invalid_argument);
    CHECK_THROWS_AS(window_attention_backward(cmd, *pool, qkv, order, offsets, 4, 4, c.scale, dout),
                    std::invalid_argument);  // head dimension 4
}

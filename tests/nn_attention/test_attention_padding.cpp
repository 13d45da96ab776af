// The window rule against the release's literal padding route (Pointcept's
// get_padding_and_inverse): same windows, so the same outputs up to summation order.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <random>
#include <vector>

#include "engine/vk/commands.h"
#include "nn/ops/attention.h"
#include "nn/tensor.h"
#include "tests/gpu_fixture.h"
#include "tests/reference/nn_attention_ref.h"

using namespace pg;

namespace {

struct Input {
    std::vector<float> qkv;
    std::vector<int32_t> order, offsets;
};

Input random_input(const std::vector<int>& sizes, int channels, uint64_t seed) {
    Input in;
    in.offsets = {0};
    for (int s : sizes) in.offsets.push_back(in.offsets.back() + s);
    const size_t n = size_t(in.offsets.back());
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    in.qkv.resize(n * 3 * size_t(channels));
    for (float& x : in.qkv) x = u(rng);
    in.order.resize(n);
    std::iota(in.order.begin(), in.order.end(), 0);
    std::shuffle(in.order.begin(), in.order.end(), rng);
    return in;
}

double max_difference(const std::vector<double>& a, const std::vector<double>& b) {
    double worst = 0;
    for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(a[i] - b[i]));
    return worst;
}

}  // namespace

TEST_CASE("window rule equals the release's padded windows (CPU)") {
    std::mt19937 rng(7);
    for (int trial = 0; trial < 60; ++trial) {
        const int patch = 1 + int(rng() % 24);
        std::vector<int> sizes(1 + rng() % 4);
        for (int& s : sizes) s = 1 + int(rng() % (3 * patch + 5));
        if (trial == 0) sizes = {patch, 2 * patch, 2 * patch + 1, patch - 1 > 0 ? patch - 1 : 1};
        const int heads = 1 + int(rng() % 2);
        const Input in = random_input(sizes, 4 * heads, rng());
        const double scale = 0.5;
        INFO("trial " << trial << ", patch " << patch);
        const auto direct = test::ref::window_attention(in.qkv, in.order, in.offsets, heads, patch, scale);
        const auto padded = test::ref::window_attention_padded(in.qkv, in.order, in.offsets, heads, patch, scale);
        REQUIRE(direct.size() == padded.size());
        CHECK(max_difference(direct, padded) <= 1e-12);
    }
}

TEST_CASE("GPU window attention equals the release's padded windows") {
    auto& ctx = test::gpu();
    auto pool = nn::Pool::create(ctx);
    const std::vector<int> sizes = {1100, 300, 2048, 1, 1500};
    const int heads = 2, patch = 1024, channels = 32;
    const Input in = random_input(sizes, channels, 99);
    const int64_t n = int64_t(in.order.size());
    nn::Tensor qkv = nn::upload_tensor(*pool, in.qkv, {n, 3 * channels}, nn::DType::F32);
    nn::Tensor order = nn::upload_tensor(*pool, in.order, {n}, nn::DType::I32);
    nn::Tensor offsets = nn::upload_tensor(*pool, in.offsets, {int64_t(in.offsets.size())}, nn::DType::I32);
    const auto want = test::ref::window_attention_padded(in.qkv, in.order, in.offsets, heads, patch, 0.25);
    for (auto kernel : {nn::ops::AttentionKernel::Gpu, nn::ops::AttentionKernel::Cpu}) {
        vk::CommandList cmd(ctx);
        nn::Tensor out = nn::ops::window_attention(cmd, *pool, qkv, order, offsets, heads, patch, 0.25f, kernel);
        cmd.submit_and_wait();
        const auto got = nn::download_tensor<float>(ctx, out);
        REQUIRE(got.size() == want.size());
        double worst = 0;
        for (size_t i = 0; i < got.size(); ++i) worst = std::max(worst, std::abs(double(got[i]) - want[i]));
        INFO("kernel " << (kernel == nn::ops::AttentionKernel::Gpu ? "gpu" : "cpu"));
        CHECK(worst <= 1e-5);
    }
}

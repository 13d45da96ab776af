// AdamW and the OneCycle schedule against values computed by PyTorch 1.13
// (torch.optim.AdamW in float64; torch.optim.lr_scheduler.OneCycleLR).
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "nn/train/optimizer.h"
#include "tests/gpu_fixture.h"
#include "tests/reference/nn_dense_ref.h"

using namespace pg;

TEST_CASE("AdamW: three steps match torch.optim.AdamW") {
    auto pool = nn::Pool::create(pg::test::gpu());
    nn::Tensor p = nn::upload_tensor(*pool, std::vector<float>{0.5f, -1.0f, 2.0f, 0.0f}, {4}, nn::DType::F32);
    const std::vector<std::vector<float>> grads = {{0.1f, -0.2f, 0.3f, 0.0f}, {0.05f, 0.1f, -0.4f, 1.0f},
                                                   {-0.3f, 0.2f, 0.1f, -1.0f}};
    nn::train::AdamW opt(*pool, {0.999, 1e-8, 0.05});
    vk::CommandList cmd(pg::test::gpu());
    std::vector<nn::Tensor> keep;  // gradients stay alive until the stream ran
    for (const auto& g : grads) {
        keep.push_back(nn::upload_tensor(*pool, g, {4}, nn::DType::F32));
        opt.step(cmd, {p}, {keep.back()}, 0.01, 0.9);
    }
    cmd.submit_and_wait();
    const auto got = nn::download_tensor<float>(pg::test::gpu(), p);
    const double want[4] = {0.4834154740071437, -0.9885756770835078, 1.9891587522276661, -0.006985825054155054};
    for (int i = 0; i < 4; ++i) CHECK(got[size_t(i)] == Approx(want[i]).margin(2e-6));
    CHECK(opt.steps() == 3);
    CHECK_THROWS_AS(opt.step(cmd, {p}, {}, 0.01, 0.9), std::invalid_argument);
}

// Several tensors go in one dispatch (nn/adamw's sets): every tensor of a model, whatever its
// size and place in the list, gets its own update, as with one tensor per dispatch.
TEST_CASE("AdamW: a model's many tensors of different sizes each get their own update") {
    auto pool = nn::Pool::create(pg::test::gpu());
    const std::vector<int64_t> sizes = {1, 300, 7, 256, 257, 1, 4096, 33, 2, 999, 64, 5, 12, 3000, 8, 1};
    std::vector<nn::Tensor> params, grads;
    std::vector<std::vector<float>> p0, g0;
    for (size_t t = 0; t < sizes.size(); ++t) {
        p0.push_back(pg::test::ref::random_uniform(size_t(sizes[t]), uint32_t(100 + t), -2.0f, 2.0f));
        g0.push_back(pg::test::ref::random_uniform(size_t(sizes[t]), uint32_t(200 + t), -1.0f, 1.0f));
        params.push_back(nn::upload_tensor(*pool, p0.back(), {sizes[t]}, nn::DType::F32));
        grads.push_back(nn::upload_tensor(*pool, g0.back(), {sizes[t]}, nn::DType::F32));
    }
    const double lr = 0.02, beta1 = 0.9, beta2 = 0.999, eps = 1e-8, wd = 0.05;
    nn::train::AdamW opt(*pool, {beta2, eps, wd});
    vk::CommandList cmd(pg::test::gpu());
    opt.step(cmd, params, grads, lr, beta1);
    cmd.submit_and_wait();
    for (size_t t = 0; t < sizes.size(); ++t) {
        INFO("tensor " << t << " of " << sizes[t] << " elements");
        const auto got = nn::download_tensor<float>(pg::test::gpu(), params[t]);
        REQUIRE(got.size() == size_t(sizes[t]));
        for (size_t i = 0; i < got.size(); ++i) {
            // First step from zero moments: m = (1 - b1) g, v = (1 - b2) g^2.
            const double g = g0[t][i], m = (1 - beta1) * g, v = (1 - beta2) * g * g;
            const double want = p0[t][i] * (1 - lr * wd) - lr / (1 - beta1) * m / (std::sqrt(v / (1 - beta2)) + eps);
            CHECK(got[i] == Approx(want).margin(2e-6));
        }
    }
}

TEST_CASE("OneCycle: learning rate and beta1 match torch's OneCycleLR") {
    nn::train::OneCycle s;
    s.max_lr = 0.002;
    s.total_steps = 100;
    s.pct_start = 0.05;
    s.div_factor = 10;
    s.final_div_factor = 1000;
    CHECK(s.lr(0) == Approx(0.0002));
    CHECK(s.lr(2) == Approx(0.0011));
    CHECK(s.lr(4) == Approx(0.002));
    CHECK(s.lr(5) == Approx(0.001999453312015192));
    CHECK(s.lr(50) == Approx(0.0010496787962977548));
    CHECK(s.lr(99) == Approx(2.0000000000000002e-07));
    CHECK(s.beta1(0) == Approx(0.95));
    CHECK(s.beta1(4) == Approx(0.85));
    CHECK(s.beta1(50) == Approx(0.8975208122663388));
    CHECK(s.beta1(99) == Approx(0.95));
}

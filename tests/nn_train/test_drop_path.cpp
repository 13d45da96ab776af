#include <catch2/catch.hpp>

#include "nn/train/drop_path.h"
#include "tests/gpu_fixture.h"
#include "tests/nn_grad/grad_test_util.h"

using namespace pg;

TEST_CASE("drop path masks keep rows at 1/(1-rate) with probability 1-rate, scale_rows matches the host", "[train]") {
    auto pool = nn::Pool::create(test::gpu());
    vk::CommandList cmd(test::gpu());
    std::mt19937_64 rng(3);
    const int64_t rows = 20000, channels = 5;  // over vkCmdUpdateBuffer's 64 KiB: written in chunks
    nn::Tensor mask = nn::train::drop_path_mask(cmd, *pool, rows, 0.3, rng);
    std::vector<float> x(size_t(rows * channels));
    for (size_t i = 0; i < x.size(); ++i) x[i] = float(i % 97) * 0.25f - 7.0f;
    nn::Tensor xt = test::up(*pool, x, {rows, channels});
    nn::Tensor y = nn::train::scale_rows(cmd, *pool, xt, mask);
    cmd.submit_and_wait();
    const std::vector<float> m = test::down(*pool, mask), yv = test::down(*pool, y);
    size_t dropped = 0;
    size_t other = 0;
    for (float v : m) {
        other += v != 0.0f && v != float(1.0 / 0.7);
        dropped += v == 0.0f;
    }
    CHECK(other == 0);
    CHECK(double(dropped) / double(rows) == Approx(0.3).margin(0.015));
    size_t wrong = 0;
    for (int64_t r = 0; r < rows; ++r)
        for (int64_t c = 0; c < channels; ++c) wrong += yv[size_t(r * channels + c)] != x[size_t(r * channels + c)] * m[size_t(r)];
    CHECK(wrong == 0);
    CHECK_THROWS_AS(nn::train::scale_rows(cmd, *pool, xt, test::up(*pool, {1.0f}, {1})), std::invalid_argument);
    CHECK_THROWS_AS(nn::train::drop_path_mask(cmd, *pool, 4, 1.0, rng), std::invalid_argument);
}

// Ad hoc timings, hidden from the default run: pg_tests_nn_attention "[bench]" -s
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstdio>
#include <numeric>
#include <random>
#include <vector>

#include <sys/resource.h>

#include "engine/vk/commands.h"
#include "engine/vk/context.h"
#include "nn/ops/attention.h"
#include "nn/tensor.h"
#include "tests/gpu_fixture.h"

using namespace pg;

namespace {

// CPU seconds of the whole process (lavapipe's worker threads included): steadier than wall
// time on a shared machine.
double cpu_seconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

void time_attention(int64_t n, int channels, int heads, int patch, int repeats) {
    auto& ctx = test::gpu();
    auto pool = nn::Pool::create(ctx);
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::vector<float> qkv(size_t(n) * 3 * size_t(channels));
    for (float& x : qkv) x = u(rng);
    std::vector<int32_t> order(static_cast<size_t>(n));
    std::iota(order.begin(), order.end(), 0);
    std::shuffle(order.begin(), order.end(), rng);
    const std::vector<int32_t> offsets = {0, int32_t(n)};
    nn::Tensor t_qkv = nn::upload_tensor(*pool, qkv, {n, 3 * int64_t(channels)}, nn::DType::F32);
    nn::Tensor t_order = nn::upload_tensor(*pool, order, {n}, nn::DType::I32);
    nn::Tensor t_offsets = nn::upload_tensor(*pool, offsets, {2}, nn::DType::I32);
    vk::CommandList cmd(ctx);
    const float scale = 1.0f / std::sqrt(float(channels / heads));
    const auto w0 = std::chrono::steady_clock::now();
    nn::ops::window_attention(cmd, *pool, t_qkv, t_order, t_offsets, heads, patch, scale);  // builds the pipeline
    cmd.submit_and_wait();
    const double first = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - w0).count();
    double best = 1e30, best_cpu = 1e30;
    for (int r = 0; r < repeats; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        const double c0 = cpu_seconds();
        nn::ops::window_attention(cmd, *pool, t_qkv, t_order, t_offsets, heads, patch, scale);
        cmd.submit_and_wait();
        best_cpu = std::min(best_cpu, 1e3 * (cpu_seconds() - c0));
        best = std::min(best, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    // 2 matrix products (QK^T, PV) of 2 flops per multiply-add, over min(patch, n) keys.
    const double flops = 4.0 * double(n) * double(std::min<int64_t>(patch, n)) * channels;
    std::printf("window_attention on %s: N=%lld C=%d H=%d K=%d: %.2f ms (%.2f ms of CPU time), %.2f GFLOP/s; "
                "first call %.0f ms\n",
                ctx.info().name.c_str(), (long long)n, channels, heads, patch, best, best_cpu, flops / best * 1e-6, first);
}

}  // namespace

TEST_CASE("window attention timings", "[.][bench]") {
    if (const char* e = std::getenv("PG_ATTN_BENCH")) {  // "N,C,H,K" for ad hoc runs
        long long n; int c, h, k;
        if (std::sscanf(e, "%lld,%d,%d,%d", &n, &c, &h, &k) == 4) time_attention(n, c, h, k, std::getenv("PG_ATTN_REPEATS") ? std::atoi(std::getenv("PG_ATTN_REPEATS")) : 2);
        return;
    }
    time_attention(8192, 32, 2, 1024, 3);
    time_attention(8192, 64, 4, 1024, 3);
    time_attention(1024, 256, 16, 1024, 3);
}

// Throughput of the dense ops on the shapes PTv3 runs (hidden: run with "[.bench]"). Prints
// GFLOP/s per GEMM kernel family and milliseconds per norm/elementwise op; asserts nothing.
#include <catch2/catch.hpp>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include <sys/resource.h>

#include "engine/vk/context.h"
#include "nn/ops/elementwise.h"
#include "nn/ops/linear.h"
#include "nn/ops/norm.h"

using namespace pg;
using nn::DType;
using nn::Tensor;

namespace {

Tensor random_tensor(nn::Pool& pool, std::vector<int64_t> shape, uint32_t seed) {
    int64_t n = 1;
    for (int64_t s : shape) n *= s;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> d(-1.0f, 1.0f);
    std::vector<float> v(static_cast<size_t>(n));
    for (auto& x : v) x = d(rng);
    return nn::upload_tensor(pool, v, std::move(shape), DType::F32);
}

// Neighbour table with about `present` of the taps found, like a surface scan's.
Tensor random_neighbors(nn::Pool& pool, int64_t M, int64_t T, int64_t P, double present, uint32_t seed) {
    std::mt19937 rng(seed);
    std::vector<int32_t> v(size_t(M * T));
    for (auto& j : v) j = std::uniform_real_distribution<double>(0, 1)(rng) < present ? int32_t(rng() % P) : -1;
    return nn::upload_tensor(pool, v, {M, T}, DType::I32);
}

// Its own context without the validation layer, whose per-command work would be timed too.
vk::Context& bench_context() {
    static vk::Context* ctx = [] {
        vk::ContextOptions o;
        o.quiet = true;
        return new vk::Context(o);  // leaked like the test fixture's
    }();
    return *ctx;
}

// CPU seconds of this process (lavapipe's worker threads included): on a CPU device this is
// the work done, whatever else the machine is running.
double cpu_seconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

struct Shape {
    const char* what;
    int64_t M, K, N;
    int64_t taps;  // 0: linear, else sparse conv with K = taps * Cin
};

void bench(nn::Pool& pool, const Shape& s, nn::ops::GemmPath path) {
    nn::ops::set_gemm_path(path);
    Tensor w = random_tensor(pool, {s.N, s.K}, 2), b = random_tensor(pool, {s.N}, 3);
    Tensor x, nbr;
    if (s.taps) {
        const int64_t cin = s.K / s.taps;
        x = random_tensor(pool, {s.M, cin}, 1);
        nbr = random_neighbors(pool, s.M, s.taps, s.M, 0.35, 4);
    } else {
        x = random_tensor(pool, {s.M, s.K}, 1);
    }
    vk::CommandList cmd(pool.context());
    auto run = [&] { return s.taps ? nn::ops::sparse_conv(cmd, pool, x, nbr, w, b) : nn::ops::linear(cmd, pool, x, w, b); };
    run();
    cmd.submit_and_wait();  // compile and warm up
    const int reps = 2.0 * s.M * s.N * s.K > 1e9 ? 1 : 3;
    cmd.begin_pass("gemm");
    for (int r = 0; r < reps; ++r) run();
    const double cpu0 = cpu_seconds();
    cmd.submit_and_wait();
    const double cpu_ms = (cpu_seconds() - cpu0) * 1e3 / reps;
    const double ms = cmd.total_ms() / reps, flop = 2.0 * double(s.M) * double(s.N) * double(s.K);
    std::printf("%-6s %-32s M=%5lld K=%6lld N=%5lld %9.2f ms %7.2f GFLOP/s %7.2f GFLOP per CPU-s\n",
                path == nn::ops::GemmPath::Lanes ? "lanes" : "tiled", s.what, (long long)s.M, (long long)s.K,
                (long long)s.N, ms, flop / (ms * 1e6), flop / (cpu_ms * 1e6));
    nn::ops::set_gemm_path(nn::ops::GemmPath::Auto);
}

}  // namespace

TEST_CASE("linear and sparse_conv throughput on PTv3 shapes", "[.bench]") {
    auto pool = nn::Pool::create(bench_context());
    std::printf("device: %s\n", pool->context().info().name.c_str());
    const Shape shapes[] = {
        {"qkv, level 0", 8192, 32, 96, 0},
        {"fc1, level 0", 8192, 32, 128, 0},
        {"fc2, level 0", 8192, 128, 32, 0},
        {"linear [8192,864]x[32,864]", 8192, 864, 32, 0},
        {"conv 3x3x3, Cin 32 (K 864)", 8192, 864, 32, 27},
        {"conv 5x5x5, Cin 2 (K 250)", 8192, 250, 32, 125},
        {"linear [1024,3456]x[128,3456]", 1024, 3456, 128, 0},
        {"conv 3x3x3, Cin 128 (K 3456)", 1024, 3456, 128, 27},
        {"linear [256,13824]x[512,13824]", 256, 13824, 512, 0},
        {"linear [61,13824]x[512,13824]", 61, 13824, 512, 0},
    };
    const char* only = std::getenv("PG_BENCH_PATH");
    for (const Shape& s : shapes) {
        if (!only || std::string(only) == "lanes") bench(*pool, s, nn::ops::GemmPath::Lanes);
        if (!only || std::string(only) == "tiled") bench(*pool, s, nn::ops::GemmPath::Tiled);
    }
}

TEST_CASE("norm and elementwise op times on PTv3 shapes", "[.bench]") {
    auto pool = nn::Pool::create(bench_context());
    for (auto [M, C] : {std::pair<int64_t, int64_t>{8192, 32}, {8192, 128}, {1024, 512}}) {
        Tensor x = random_tensor(*pool, {M, C}, 1), y = random_tensor(*pool, {M, C}, 2);
        Tensor g = random_tensor(*pool, {C}, 3), b = random_tensor(*pool, {C}, 4);
        std::vector<float> ones(static_cast<size_t>(C), 1.0f);
        Tensor var = nn::upload_tensor(*pool, ones, {C}, DType::F32);
        std::vector<int32_t> idx(static_cast<size_t>(M));
        for (size_t i = 0; i < idx.size(); ++i) idx[i] = int32_t((i * 7919) % size_t(M));
        Tensor ti = nn::upload_tensor(*pool, idx, {M}, DType::I32);
        vk::CommandList cmd(pool->context());
        auto time = [&](const char* name, auto op) {
            op();
            cmd.submit_and_wait();
            const double cpu0 = cpu_seconds();
            cmd.begin_pass(name);
            for (int r = 0; r < 5; ++r) op();
            cmd.submit_and_wait();
            std::printf("%-14s [%5lld,%4lld] %8.3f ms %8.3f CPU-ms\n", name, (long long)M, (long long)C,
                        cmd.total_ms() / 5, (cpu_seconds() - cpu0) * 1e3 / 5);
        };
        time("layer_norm", [&] { nn::ops::layer_norm(cmd, *pool, x, g, b, 1e-5f); });
        time("batch_norm", [&] { nn::ops::batch_norm(cmd, *pool, x, g, var, g, b, 1e-3f, false); });
        time("bn+gelu", [&] { nn::ops::batch_norm(cmd, *pool, x, g, var, g, b, 1e-3f, true); });
        time("gelu", [&] { nn::ops::gelu(cmd, *pool, x); });
        time("add", [&] { nn::ops::add(cmd, *pool, x, y); });
        time("gather_rows", [&] { nn::ops::gather_rows(cmd, *pool, x, ti); });
        time("add_gathered", [&] { nn::ops::add_gathered(cmd, *pool, x, y, ti); });
    }
}

// Serialized pooling: clusters, segment max and the next level's codes, grid and batch, GPU
// against the reference.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include "nn/ops/pooling.h"
#include "nn/ops/serialize.h"
#include "tests/gpu_fixture.h"
#include "tests/reference/nn_index_ref.h"

using namespace pg;
using nn::DType;
namespace ref = pg::test::ref;

namespace {

// Clusters on the GPU and the reference, compared field by field.
nn::ops::Clusters check_clusters(nn::Pool& pool, const std::vector<uint64_t>& codes, int shift, int code_bits = 64) {
    INFO("n = " << codes.size() << ", shift " << shift << ", code_bits " << code_bits);
    const int64_t n = int64_t(codes.size());
    nn::Tensor t = nn::upload_tensor(pool, codes, {n}, DType::U64);
    vk::CommandList cmd(pool.context());
    nn::ops::Clusters c = nn::ops::pool_clusters(cmd, pool, t, shift, code_bits);
    ref::Clusters expect = ref::pool_clusters(codes, shift);
    REQUIRE(c.count == int64_t(expect.head.size()));
    CHECK(c.ptr.shape == std::vector<int64_t>{c.count + 1});
    CHECK(c.head.shape == std::vector<int64_t>{c.count});
    auto& ctx = pool.context();
    CHECK(nn::download_tensor<int32_t>(ctx, c.cluster) == expect.cluster);
    CHECK(nn::download_tensor<int32_t>(ctx, c.members) == expect.members);
    CHECK(nn::download_tensor<int32_t>(ctx, c.ptr) == expect.ptr);
    CHECK(nn::download_tensor<int32_t>(ctx, c.head) == expect.head);
    return c;
}

std::vector<uint64_t> z_codes(const ref::Cloud& c) {
    int m = 0;
    for (int32_t g : c.grid) m = std::max(m, g);
    return ref::serialize_codes(c.grid, c.batch, 0, nn::ops::serialization_depth(m));
}

}  // namespace

TEST_CASE("pooling: GPU clusters equal torch.unique on code >> shift") {
    auto pool = nn::Pool::create(pg::test::gpu());
    check_clusters(*pool, {12345}, 3);
    check_clusters(*pool, z_codes(ref::random_cloud(4000, 3, 60, 21, true)), 3);
    check_clusters(*pool, z_codes(ref::random_cloud(4000, 3, 60, 21, true)), 3, 3 * 6 + 2);
    check_clusters(*pool, z_codes(ref::random_cloud(10000, 2, 1 << 16, 22, true)), 9);
    std::vector<uint64_t> same(3100, 7);  // one cluster of everything
    check_clusters(*pool, same, 3);
}

TEST_CASE("pooling: segment max and the next level's codes, grid and batch") {
    auto pool = nn::Pool::create(pg::test::gpu());
    auto& ctx = pool->context();
    std::mt19937_64 rng(31);
    for (size_t n : {size_t(1), size_t(2500)}) {
        ref::Cloud c = ref::random_cloud(n, 2, 50, 30 + n, true);
        const int64_t rows = int64_t(c.size());
        std::vector<uint64_t> codes = z_codes(c);
        nn::Tensor code_t = nn::upload_tensor(*pool, codes, {rows}, DType::U64);
        nn::Tensor grid_t = nn::upload_tensor(*pool, c.grid, {rows, 3}, DType::I32);
        nn::Tensor batch_t = nn::upload_tensor(*pool, c.batch, {rows}, DType::I32);
        vk::CommandList cmd(ctx);
        nn::ops::Clusters cl = nn::ops::pool_clusters(cmd, *pool, code_t, 3);
        ref::Clusters expect = ref::pool_clusters(codes, 3);
        REQUIRE(cl.count == int64_t(expect.head.size()));

        nn::Tensor next_codes = nn::ops::pool_codes(cmd, *pool, code_t, cl, 3);
        nn::Tensor next_grid = nn::ops::pool_grid(cmd, *pool, grid_t, cl, 1);
        nn::Tensor next_batch = nn::ops::gather_batch(cmd, *pool, batch_t, cl);
        std::vector<std::pair<int, std::vector<float>>> inputs;
        std::vector<nn::Tensor> outputs, keep;  // uploads write on the host at once: inputs live until the submit
        for (int channels : {1, 3, 32, 67}) {
            std::normal_distribution<float> normal;
            std::vector<float> x(size_t(rows) * channels);
            for (auto& v : x) v = normal(rng);
            nn::Tensor x_t = nn::upload_tensor(*pool, x, {rows, int64_t(channels)}, DType::F32);
            outputs.push_back(nn::ops::segment_max(cmd, *pool, x_t, cl));
            keep.push_back(x_t);
            inputs.emplace_back(channels, std::move(x));
        }
        cmd.submit_and_wait();

        INFO("n = " << rows);
        std::vector<uint64_t> codes_ref;
        std::vector<int32_t> grid_ref, batch_ref;
        for (int32_t h : expect.head) {
            codes_ref.push_back(codes[h] >> 3);
            for (int a = 0; a < 3; ++a) grid_ref.push_back(c.grid[3 * h + a] >> 1);
            batch_ref.push_back(c.batch[h]);
        }
        CHECK(nn::download_tensor<uint64_t>(ctx, next_codes) == codes_ref);
        CHECK(next_grid.shape == std::vector<int64_t>{cl.count, 3});
        CHECK(nn::download_tensor<int32_t>(ctx, next_grid) == grid_ref);
        CHECK(nn::download_tensor<int32_t>(ctx, next_batch) == batch_ref);
        for (size_t i = 0; i < inputs.size(); ++i) {
            INFO("channels " << inputs[i].first);
            CHECK(outputs[i].shape == std::vector<int64_t>{cl.count, inputs[i].first});
            CHECK(nn::download_tensor<float>(ctx, outputs[i]) ==
                  ref::segment_max(inputs[i].second, inputs[i].first, expect));
        }
    }
}

TEST_CASE("pooling: argument errors") {
    auto pool = nn::Pool::create(pg::test::gpu());
    vk::CommandList cmd(pool->context());
    CHECK_THROWS_AS(nn::ops::pool_clusters(cmd, *pool, pool->empty({4}, DType::I32), 3), std::invalid_argument);
    nn::Tensor code = nn::upload_tensor(*pool, std::vector<uint64_t>{1, 9, 17}, {3}, DType::U64);
    nn::ops::Clusters cl = nn::ops::pool_clusters(cmd, *pool, code, 3);
    CHECK(cl.count == 3);
    CHECK_THROWS_AS(nn::ops::segment_max(cmd, *pool, pool->empty({4, 2}, DType::F32), cl), std::invalid_argument);
    CHECK_THROWS_AS(nn::ops::pool_grid(cmd, *pool, pool->empty({3, 2}, DType::I32), cl, 1), std::invalid_argument);
    CHECK_THROWS_AS(nn::ops::gather_batch(cmd, *pool, pool->empty({3}, DType::I32), nn::ops::Clusters{}),
                    std::invalid_argument);
}

// Unique voxels: GPU against the std::map reference on clouds with duplicate voxels.
#include <catch2/catch.hpp>

#include <cstdint>
#include <vector>

#include "nn/ops/voxelize.h"
#include "tests/gpu_fixture.h"
#include "tests/reference/nn_index_ref.h"

using namespace pg;
using nn::DType;
namespace ref = pg::test::ref;

namespace {

void check_voxelize(nn::Pool& pool, const ref::Cloud& c, int key_bits = 64) {
    INFO("n = " << c.size() << ", key bits " << key_bits);
    const int64_t n = int64_t(c.size());
    nn::Tensor grid = nn::upload_tensor(pool, c.grid, {n, 3}, DType::I32);
    nn::Tensor batch = nn::upload_tensor(pool, c.batch, {n}, DType::I32);
    vk::CommandList cmd(pool.context());
    nn::ops::Voxels v = nn::ops::voxelize(cmd, pool, grid, batch, key_bits);
    ref::Voxels expect = ref::voxelize(c.grid, c.batch);
    REQUIRE(v.count == int64_t(expect.first.size()));
    CHECK(v.grid.shape == std::vector<int64_t>{v.count, 3});
    CHECK(v.batch.shape == std::vector<int64_t>{v.count});
    CHECK(v.first.shape == std::vector<int64_t>{v.count});
    CHECK(v.inverse.shape == std::vector<int64_t>{n});
    auto& ctx = pool.context();
    CHECK(nn::download_tensor<int32_t>(ctx, v.grid) == expect.grid);
    CHECK(nn::download_tensor<int32_t>(ctx, v.batch) == expect.batch);
    CHECK(nn::download_tensor<int32_t>(ctx, v.first) == expect.first);
    CHECK(nn::download_tensor<int32_t>(ctx, v.inverse) == expect.inverse);
}

}  // namespace

TEST_CASE("voxelize: GPU voxels equal the reference") {
    auto pool = nn::Pool::create(pg::test::gpu());
    SECTION("one point") { check_voxelize(*pool, ref::Cloud{{5, 0, 9}, {0}}); }
    SECTION("every point in one voxel") { check_voxelize(*pool, ref::random_cloud(700, 1, 1, 1, false)); }
    SECTION("many duplicates, three clouds") { check_voxelize(*pool, ref::random_cloud(5000, 3, 12, 2, false)); }
    SECTION("few duplicates, large grid entries, two clouds") {
        ref::Cloud c = ref::random_cloud(20000, 2, 1 << 16, 3, false);
        for (size_t i = 0; i < 2000; ++i) {  // copies of random earlier points
            size_t j = (i * 7919) % c.size();
            c.batch.push_back(c.batch[j]);
            c.grid.insert(c.grid.end(), {c.grid[3 * j], c.grid[3 * j + 1], c.grid[3 * j + 2]});
        }
        check_voxelize(*pool, c);
    }
    SECTION("distinct voxels keep their count") { check_voxelize(*pool, ref::random_cloud(4099, 2, 40, 4, true)); }
    SECTION("the caller's exact key bits (fewer radix passes)") {
        const ref::Cloud c = ref::random_cloud(5000, 3, 300, 2, false);
        check_voxelize(*pool, c, ref::grid_key_bits(c));
    }
}

TEST_CASE("voxelize: empty input and bad entries") {
    auto pool = nn::Pool::create(pg::test::gpu());
    vk::CommandList cmd(pool->context());
    nn::ops::Voxels v = nn::ops::voxelize(cmd, *pool, pool->empty({0, 3}, DType::I32), pool->empty({0}, DType::I32));
    CHECK(v.count == 0);
    nn::Tensor grid = nn::upload_tensor(*pool, std::vector<int32_t>{1, 2, 3, 4, -5, 6}, {2, 3}, DType::I32);
    nn::Tensor batch = nn::upload_tensor(*pool, std::vector<int32_t>{0, 0}, {2}, DType::I32);
    CHECK_THROWS_AS(nn::ops::voxelize(cmd, *pool, grid, batch), std::invalid_argument);
    CHECK_THROWS_AS(nn::ops::voxelize(cmd, *pool, grid, pool->empty({3}, DType::I32)), std::invalid_argument);
    CHECK_THROWS_AS(nn::ops::voxelize(cmd, *pool, pool->empty({2, 3}, DType::F32), batch), std::invalid_argument);
    // 2^31 - 1 in all three axes and a large batch: 31 * 3 + 8 bits do not fit a 64-bit key.
    const int32_t big = 0x7FFFFFFF;
    nn::Tensor wide = nn::upload_tensor(*pool, std::vector<int32_t>{big, big, big}, {1, 3}, DType::I32);
    nn::Tensor b1 = nn::upload_tensor(*pool, std::vector<int32_t>{200}, {1}, DType::I32);
    CHECK_THROWS_AS(nn::ops::voxelize(cmd, *pool, wide, b1), std::invalid_argument);
    // A bound one bit short of the widths is refused, not sorted wrongly.
    const ref::Cloud c = ref::random_cloud(500, 2, 300, 5, false);
    const int64_t n = int64_t(c.size());
    nn::Tensor g = nn::upload_tensor(*pool, c.grid, {n, 3}, DType::I32), b = nn::upload_tensor(*pool, c.batch, {n}, DType::I32);
    CHECK_THROWS_AS(nn::ops::voxelize(cmd, *pool, g, b, ref::grid_key_bits(c) - 1), std::invalid_argument);
    CHECK_THROWS_AS(nn::ops::voxelize(cmd, *pool, g, b, 65), std::invalid_argument);
}

// Submanifold neighbour maps: GPU against the std::map reference.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "nn/ops/neighbors.h"
#include "tests/gpu_fixture.h"
#include "tests/reference/nn_index_ref.h"

using namespace pg;
using nn::DType;
namespace ref = pg::test::ref;

namespace {

void check_neighbors(nn::Pool& pool, const ref::Cloud& c, int kernel, int key_bits = 64) {
    INFO("n = " << c.size() << ", kernel " << kernel << ", key bits " << key_bits);
    const int64_t n = int64_t(c.size());
    nn::Tensor grid = nn::upload_tensor(pool, c.grid, {n, 3}, DType::I32);
    nn::Tensor batch = nn::upload_tensor(pool, c.batch, {n}, DType::I32);
    vk::CommandList cmd(pool.context());
    nn::Tensor nbr = nn::ops::neighbor_map(cmd, pool, grid, batch, kernel, key_bits);
    cmd.submit_and_wait();
    CHECK(nbr.shape == std::vector<int64_t>{n, int64_t(kernel) * kernel * kernel});
    std::vector<int32_t> got = nn::download_tensor<int32_t>(pool.context(), nbr);
    std::vector<int32_t> expect = ref::neighbor_map(c.grid, c.batch, kernel);
    REQUIRE(got.size() == expect.size());
    size_t mismatches = 0, found = 0;
    for (size_t i = 0; i < got.size(); ++i) {
        mismatches += got[i] != expect[i];
        found += expect[i] >= 0;
    }
    CHECK(mismatches == 0);
    CHECK(found >= c.size());  // every voxel finds itself at the centre
}

}  // namespace

TEST_CASE("neighbors: GPU maps equal the reference for kernels 3 and 5") {
    auto pool = nn::Pool::create(pg::test::gpu());
    for (int kernel : {3, 5}) {
        SECTION("one voxel, kernel " + std::to_string(kernel)) {
            check_neighbors(*pool, ref::Cloud{{0, 3, 0}, {0}}, kernel);
        }
        SECTION("dense cube, two clouds at the same coordinates, kernel " + std::to_string(kernel)) {
            check_neighbors(*pool, ref::random_cloud(1500, 2, 10, 11, true), kernel);
        }
        SECTION("sparse three clouds, kernel " + std::to_string(kernel)) {
            check_neighbors(*pool, ref::random_cloud(3000, 3, 40, 12, true), kernel);
        }
        SECTION("grid entries up to 2^16 - 1, clustered blobs, kernel " + std::to_string(kernel)) {
            ref::Cloud c = ref::random_cloud(200, 2, 1 << 16, 13, true);
            ref::Cloud blob = ref::random_cloud(2000, 1, 6, 14, true);  // 6^3 voxels around each centre
            ref::Cloud all;
            for (size_t i = 0; i < c.size() && all.size() < 6000; ++i)
                for (size_t j = 0; j < 30; ++j) {
                    int32_t p[3];
                    for (int a = 0; a < 3; ++a)
                        p[a] = std::min(c.grid[3 * i + a] + blob.grid[3 * j + a], (1 << 16) - 1);
                    all.batch.push_back(c.batch[i]);
                    all.grid.insert(all.grid.end(), {p[0], p[1], p[2]});
                }
            // Blobs may overlap: keep each voxel once.
            ref::Voxels v = ref::voxelize(all.grid, all.batch);
            check_neighbors(*pool, ref::Cloud{v.grid, v.batch}, kernel);
        }
        SECTION("the caller's exact key bits (fewer radix passes), kernel " + std::to_string(kernel)) {
            const ref::Cloud c = ref::random_cloud(3000, 3, 40, 12, true);
            check_neighbors(*pool, c, kernel, ref::grid_key_bits(c));
        }
    }
}

TEST_CASE("neighbors: argument errors") {
    auto pool = nn::Pool::create(pg::test::gpu());
    vk::CommandList cmd(pool->context());
    nn::Tensor grid = pool->empty({4, 3}, DType::I32), batch = pool->empty({4}, DType::I32);
    CHECK_THROWS_AS(nn::ops::neighbor_map(cmd, *pool, grid, batch, 4), std::invalid_argument);
    CHECK_THROWS_AS(nn::ops::neighbor_map(cmd, *pool, grid, pool->empty({5}, DType::I32), 3), std::invalid_argument);
    CHECK(nn::ops::neighbor_map(cmd, *pool, pool->empty({0, 3}, DType::I32), pool->empty({0}, DType::I32), 3).shape ==
          std::vector<int64_t>{0, 27});
}

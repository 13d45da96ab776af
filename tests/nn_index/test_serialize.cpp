// Serialization codes and their stable argsort: GPU against the CPU reference, and the CPU
// reference against properties of the Hilbert curve.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <cstdint>
#include <random>
#include <vector>

#include "nn/ops/serialize.h"
#include "tests/gpu_fixture.h"
#include "tests/reference/nn_index_ref.h"

using namespace pg;
using nn::DType;
namespace ref = pg::test::ref;

namespace {

constexpr nn::ops::Order kOrders[4] = {nn::ops::Order::Z, nn::ops::Order::ZTrans, nn::ops::Order::Hilbert,
                                       nn::ops::Order::HilbertTrans};

std::vector<uint64_t> gpu_codes(nn::Pool& pool, const ref::Cloud& c, int order, int depth) {
    const int64_t n = int64_t(c.size());
    nn::Tensor grid = nn::upload_tensor(pool, c.grid, {n, 3}, DType::I32);
    nn::Tensor batch = nn::upload_tensor(pool, c.batch, {n}, DType::I32);
    vk::CommandList cmd(pool.context());
    nn::Tensor codes = nn::ops::serialize_codes(cmd, pool, grid, batch, kOrders[order], depth);
    cmd.submit_and_wait();
    return nn::download_tensor<uint64_t>(pool.context(), codes);
}

void check_codes(nn::Pool& pool, const ref::Cloud& c, int depth) {
    for (int order = 0; order < 4; ++order) {
        INFO("n = " << c.size() << ", depth " << depth << ", order " << order);
        CHECK(gpu_codes(pool, c, order, depth) == ref::serialize_codes(c.grid, c.batch, order, depth));
    }
}

int max_entry(const std::vector<int32_t>& v) { return v.empty() ? 0 : *std::max_element(v.begin(), v.end()); }

}  // namespace

TEST_CASE("serialize: the reference Hilbert code visits every cell of the cube once, in face-adjacent steps") {
    for (int depth = 1; depth <= 4; ++depth) {
        const uint32_t side = 1u << depth;
        std::vector<std::array<uint32_t, 3>> cell_of(size_t(side) * side * side, {~0u, 0, 0});
        for (uint32_t x = 0; x < side; ++x)
            for (uint32_t y = 0; y < side; ++y)
                for (uint32_t z = 0; z < side; ++z) {
                    uint64_t h = ref::hilbert_code(x, y, z, depth);
                    REQUIRE(h < cell_of.size());
                    REQUIRE(cell_of[h][0] == ~0u);
                    cell_of[h] = {x, y, z};
                }
        for (size_t h = 1; h < cell_of.size(); ++h) {
            int steps = 0;
            for (int a = 0; a < 3; ++a) steps += std::abs(int(cell_of[h][a]) - int(cell_of[h - 1][a]));
            INFO("depth " << depth << ", code " << h);
            CHECK(steps == 1);
        }
    }
}

TEST_CASE("serialize: the reference z-order code matches the bit rule") {
    CHECK(ref::z_order_code(1, 0, 0, 1) == 4);
    CHECK(ref::z_order_code(0, 1, 0, 1) == 2);
    CHECK(ref::z_order_code(0, 0, 1, 1) == 1);
    CHECK(ref::z_order_code(2, 3, 1, 2) == 0b110011);
    CHECK(ref::serialize_codes({2, 3, 1}, {1}, 1, 2)[0] == (uint64_t(1) << 6 | 0b110101));
}

TEST_CASE("serialize: GPU codes equal the reference for every order, depth and batch") {
    auto pool = nn::Pool::create(pg::test::gpu());
    SECTION("one point") {
        check_codes(*pool, ref::random_cloud(1, 1, 1, 1, false), 0);
        check_codes(*pool, ref::Cloud{{1, 0, 1}, {0}}, 1);
    }
    SECTION("three clouds, depth from the data") {
        ref::Cloud c = ref::random_cloud(3000, 3, 100, 2, false);
        check_codes(*pool, c, nn::ops::serialization_depth(max_entry(c.grid)));
    }
    SECTION("grid entries up to 2^16 - 1 (depth 16), two clouds") {
        ref::Cloud c = ref::random_cloud(5000, 2, 1 << 16, 3, false);
        c.grid[0] = (1 << 16) - 1;
        REQUIRE(nn::ops::serialization_depth(max_entry(c.grid)) == 16);
        check_codes(*pool, c, 16);
    }
    SECTION("depth 21: codes fill all 64 bits") {
        ref::Cloud c = ref::random_cloud(700, 2, 1 << 21, 4, false);
        check_codes(*pool, c, 21);
    }
    SECTION("bits above the depth are ignored") {
        ref::Cloud c = ref::random_cloud(500, 2, 1 << 10, 5, false);
        check_codes(*pool, c, 6);
    }
}

TEST_CASE("serialize: serialization_depth is the bit length of the largest entry") {
    CHECK(nn::ops::serialization_depth(0) == 0);
    CHECK(nn::ops::serialization_depth(1) == 1);
    CHECK(nn::ops::serialization_depth(98) == 7);
    CHECK(nn::ops::serialization_depth(127) == 7);
    CHECK(nn::ops::serialization_depth(128) == 8);
    CHECK(nn::ops::serialization_depth(65535) == 16);
}

TEST_CASE("serialize: sort_codes is the stable argsort on the low key bits") {
    auto pool = nn::Pool::create(pg::test::gpu());
    auto run = [&](const std::vector<uint64_t>& codes, int key_bits) {
        INFO("n = " << codes.size() << ", key_bits " << key_bits);
        const int64_t n = int64_t(codes.size());
        nn::Tensor t = nn::upload_tensor(*pool, codes, {n}, DType::U64);
        vk::CommandList cmd(pool->context());
        nn::ops::Sorted s = nn::ops::sort_codes(cmd, *pool, t, key_bits);
        cmd.submit_and_wait();
        ref::Sorted expect = ref::argsort(codes, key_bits);
        CHECK(nn::download_tensor<int32_t>(pool->context(), s.order) == expect.order);
        CHECK(nn::download_tensor<int32_t>(pool->context(), s.inverse) == expect.inverse);
        CHECK(nn::download_tensor<uint64_t>(pool->context(), t) == codes);  // the input is kept
    };
    std::mt19937_64 rng(7);
    auto random_codes = [&](size_t n, uint64_t mask) {
        std::vector<uint64_t> v(n);
        for (auto& c : v) c = rng() & mask;
        return v;
    };
    run({42}, 64);
    run(random_codes(3073, 0xFF), 64);              // many ties, one block and a bit
    run(random_codes(40000, ~uint64_t(0)), 64);     // all 64 bits
    run(random_codes(9000, (1ull << 23) - 1), 23);  // PTv3-like: 3 depth + batch bits
    run(random_codes(5000, ~uint64_t(0)), 40);      // bits above key_bits are ignored
    // The per-context sorter state can be dropped between streams and comes back on demand.
    nn::ops::release_index_state(pool->context());
    run(random_codes(777, 0xFFFF), 16);
}

TEST_CASE("serialize: shape and argument errors are reported") {
    auto pool = nn::Pool::create(pg::test::gpu());
    vk::CommandList cmd(pool->context());
    nn::Tensor grid = pool->empty({4, 2}, DType::I32), batch = pool->empty({4}, DType::I32);
    CHECK_THROWS_AS(nn::ops::serialize_codes(cmd, *pool, grid, batch, nn::ops::Order::Z, 4), std::invalid_argument);
    nn::Tensor grid3 = pool->empty({4, 3}, DType::I32), batch5 = pool->empty({5}, DType::I32);
    CHECK_THROWS_AS(nn::ops::serialize_codes(cmd, *pool, grid3, batch5, nn::ops::Order::Z, 4), std::invalid_argument);
    CHECK_THROWS_AS(nn::ops::serialize_codes(cmd, *pool, grid3, batch, nn::ops::Order::Z, 22), std::invalid_argument);
    CHECK_THROWS_AS(nn::ops::sort_codes(cmd, *pool, grid3, 64), std::invalid_argument);
}

// Backward of linear and submanifold sparse conv (nn/train/grad_ops.h): GPU == CPU reference,
// CPU reference == central finite differences, bit-identical reruns, the conv map's symmetry.
#include <catch2/catch.hpp>

#include <cstdint>
#include <cstring>
#include <random>
#include <stdexcept>
#include <vector>

#include "nn/ops/linear.h"
#include "nn/ops/neighbors.h"
#include "nn/train/grad_ops.h"
#include "tests/gpu_fixture.h"
#include "tests/nn_grad/grad_test_util.h"
#include "tests/reference/nn_dense_ref.h"
#include "tests/reference/nn_grad_ref.h"
#include "tests/reference/nn_index_ref.h"

using namespace pg;
using nn::DType;
using nn::Tensor;
namespace ref = pg::test::ref;
namespace gref = pg::test::ref::grad;

using pg::test::down;
using pg::test::same_bits;
using pg::test::up;

namespace {




struct LinearCase {
    std::vector<float> x, w, dy;
};

LinearCase linear_case(int64_t M, int64_t K, int64_t N, uint32_t seed) {
    return {ref::random_uniform(size_t(M * K), seed), ref::random_uniform(size_t(N * K), seed + 1),
            ref::random_uniform(size_t(M * N), seed + 2)};
}

// Runs the GPU backward; returns dx, dw, db.
std::vector<std::vector<float>> gpu_linear(nn::Pool& pool, const LinearCase& c, int64_t M, int64_t K, int64_t N) {
    // Uploads act at once: all of them before recording (see tensor.h).
    Tensor x = up(pool, c.x, {M, K}), w = up(pool, c.w, {N, K}), dy = up(pool, c.dy, {M, N});
    vk::CommandList cmd(pool.context());
    auto g = nn::grad::linear_backward(cmd, pool, x, w, dy);
    cmd.submit_and_wait();
    CHECK(g.dx.shape == std::vector<int64_t>{M, K});
    CHECK(g.dw.shape == std::vector<int64_t>{N, K});
    CHECK(g.db.shape == std::vector<int64_t>{N});
    return {down(pool, g.dx), down(pool, g.dw), down(pool, g.db)};
}

void check_linear(nn::Pool& pool, int64_t M, int64_t K, int64_t N, uint32_t seed) {
    INFO("M=" << M << " K=" << K << " N=" << N);
    const LinearCase c = linear_case(M, K, N, seed);
    const auto got = gpu_linear(pool, c, M, K, N);
    const auto want = gref::linear_backward(gref::to_double(c.x), gref::to_double(c.w), gref::to_double(c.dy), M, K, N);
    CHECK(gref::worst_error(got[0], want.dx, 1e-5) <= 1.0);
    CHECK(gref::worst_error_normwise(got[1], want.dw, 1e-5) <= 1.0);
    CHECK(gref::worst_error_normwise(got[2], want.db, 1e-5) <= 1.0);
}

struct ConvCase {
    std::vector<int32_t> nbr;
    int64_t P = 0, T = 0;
    std::vector<float> x, w, dy;
};

ConvCase conv_case(size_t n, int extent, int kernel, bool distinct, int64_t cin, int64_t cout, uint32_t seed) {
    const ref::Cloud cloud = ref::random_cloud(n, 2, extent, seed, distinct);
    ConvCase c;
    c.nbr = ref::neighbor_map(cloud.grid, cloud.batch, kernel);
    c.P = int64_t(cloud.size());
    c.T = int64_t(kernel) * kernel * kernel;
    c.x = ref::random_uniform(size_t(c.P * cin), seed + 1);
    c.w = ref::random_uniform(size_t(cout * c.T * cin), seed + 2, -0.3f, 0.3f);
    c.dy = ref::random_uniform(size_t(c.P * cout), seed + 3);
    return c;
}

std::vector<std::vector<float>> gpu_conv(nn::Pool& pool, const ConvCase& c, int64_t cin, int64_t cout) {
    Tensor nbr = nn::upload_tensor(pool, c.nbr, {c.P, c.T}, DType::I32);
    Tensor x = up(pool, c.x, {c.P, cin}), w = up(pool, c.w, {cout, c.T * cin}), dy = up(pool, c.dy, {c.P, cout});
    vk::CommandList cmd(pool.context());
    auto g = nn::grad::sparse_conv_backward(cmd, pool, x, nbr, w, dy);
    cmd.submit_and_wait();
    CHECK(g.dx.shape == std::vector<int64_t>{c.P, cin});
    CHECK(g.dw.shape == std::vector<int64_t>{cout, c.T * cin});
    return {down(pool, g.dx), down(pool, g.dw), down(pool, g.db)};
}

void check_conv(nn::Pool& pool, size_t n, int extent, int kernel, int64_t cin, int64_t cout, uint32_t seed) {
    const ConvCase c = conv_case(n, extent, kernel, true, cin, cout, seed);
    INFO("P=" << c.P << " T=" << c.T << " cin=" << cin << " cout=" << cout);
    REQUIRE(gref::symmetric_map(c.nbr, c.P, c.T));
    const auto got = gpu_conv(pool, c, cin, cout);
    const auto want = gref::conv_backward(gref::to_double(c.x), c.nbr, gref::to_double(c.w), gref::to_double(c.dy), c.P,
                                          c.T, cin, cout);
    CHECK(gref::worst_error(got[0], want.dx, 1e-5) <= 1.0);
    CHECK(gref::worst_error_normwise(got[1], want.dw, 1e-5) <= 1.0);
    CHECK(gref::worst_error_normwise(got[2], want.db, 1e-5) <= 1.0);
}

}  // namespace

TEST_CASE("linear backward matches the CPU reference at edge and large sizes") {
    auto pool = nn::Pool::create(pg::test::gpu());
    check_linear(*pool, 1, 1, 1, 1);
    check_linear(*pool, 1, 7, 3, 2);
    check_linear(*pool, 5, 3, 7, 3);
    check_linear(*pool, 37, 70, 33, 4);     // no dimension a multiple of a tile
    check_linear(*pool, 300, 96, 200, 5);
    check_linear(*pool, 8192, 64, 64, 6);   // a PTv3 batch: dw sums over 8192 rows
    check_linear(*pool, 4099, 33, 130, 7);  // rows not a multiple of 8 (padded transposes)
    check_linear(*pool, 40000, 8, 12, 8);   // dw over many windows of rows
    check_linear(*pool, 8192, 16, 2, 9);    // a 2-class head: dw's GEMM puts its columns on the 16 side
}

TEST_CASE("linear backward reference matches finite differences") {
    const int64_t M = 3, K = 4, N = 5;
    const auto c = linear_case(M, K, N, 11);
    const auto x = gref::to_double(c.x), w = gref::to_double(c.w), dy = gref::to_double(c.dy);
    const auto b = gref::to_double(ref::random_uniform(size_t(N), 14));
    const auto g = gref::linear_backward(x, w, dy, M, K, N);
    // loss = <dy, y>, so its gradient is the backward of dy.
    auto loss = [&](const gref::Vec& xx, const gref::Vec& ww, const gref::Vec& bb) {
        return gref::dot(dy, gref::linear_forward(xx, ww, bb, M, K, N));
    };
    CHECK(gref::worst_error(g.dx, gref::numeric_gradient([&](const gref::Vec& v) { return loss(v, w, b); }, x), 1e-7) <= 1);
    CHECK(gref::worst_error(g.dw, gref::numeric_gradient([&](const gref::Vec& v) { return loss(x, v, b); }, w), 1e-7) <= 1);
    CHECK(gref::worst_error(g.db, gref::numeric_gradient([&](const gref::Vec& v) { return loss(x, w, v); }, b), 1e-7) <= 1);
}

TEST_CASE("linear backward is bit-identical across runs") {
    auto pool = nn::Pool::create(pg::test::gpu());
    const int64_t M = 5000, K = 48, N = 40;
    const auto c = linear_case(M, K, N, 21);
    const auto a = gpu_linear(*pool, c, M, K, N), b = gpu_linear(*pool, c, M, K, N);
    for (size_t i = 0; i < a.size(); ++i) CHECK(same_bits(a[i], b[i]));
}

TEST_CASE("sparse_conv backward matches the CPU reference with missing neighbours") {
    auto pool = nn::Pool::create(pg::test::gpu());
    check_conv(*pool, 1, 4, 3, 3, 2, 31);       // one voxel: only the centre tap
    check_conv(*pool, 40, 6, 3, 5, 7, 32);      // sparse: most taps missing
    check_conv(*pool, 300, 8, 3, 16, 24, 33);
    check_conv(*pool, 150, 6, 5, 4, 6, 34);     // kernel 5 (125 taps), as the embedding
    check_conv(*pool, 2000, 14, 3, 32, 32, 35);
    check_conv(*pool, 40000, 30, 3, 2, 3, 36);  // dw over many windows of rows
}

TEST_CASE("sparse_conv backward reference matches finite differences") {
    const int64_t cin = 2, cout = 3;
    // 8 voxels in a 3^3 box of one cloud: most taps of most voxels are missing.
    const ConvCase c = conv_case(16, 3, 3, true, cin, cout, 41);
    REQUIRE(c.P > 1);
    const auto x = gref::to_double(c.x), w = gref::to_double(c.w), dy = gref::to_double(c.dy);
    const auto b = gref::to_double(ref::random_uniform(size_t(cout), 45));
    const auto g = gref::conv_backward(x, c.nbr, w, dy, c.P, c.T, cin, cout);
    auto loss = [&](const gref::Vec& xx, const gref::Vec& ww, const gref::Vec& bb) {
        return gref::dot(dy, gref::conv_forward(xx, c.nbr, ww, bb, c.P, c.T, cin, cout));
    };
    CHECK(gref::worst_error(g.dx, gref::numeric_gradient([&](const gref::Vec& v) { return loss(v, w, b); }, x), 1e-7) <= 1);
    CHECK(gref::worst_error(g.dw, gref::numeric_gradient([&](const gref::Vec& v) { return loss(x, v, b); }, w), 1e-7) <= 1);
    CHECK(gref::worst_error(g.db, gref::numeric_gradient([&](const gref::Vec& v) { return loss(x, w, v); }, b), 1e-7) <= 1);
}

TEST_CASE("sparse_conv backward is bit-identical across runs") {
    auto pool = nn::Pool::create(pg::test::gpu());
    const ConvCase c = conv_case(1500, 12, 3, true, 16, 16, 51);
    const auto a = gpu_conv(*pool, c, 16, 16), b = gpu_conv(*pool, c, 16, 16);
    for (size_t i = 0; i < a.size(); ++i) CHECK(same_bits(a[i], b[i]));
}

TEST_CASE("sparse_conv backward over the table's rulebook gives the table's gradients, bit for bit") {
    // Training passes the forward's rulebook; channels the rulebook kernels take (dy's 32 % 16)
    // and ones they do not (16 % 16, but the forward's 8: dx's own output), both matching the reference.
    auto pool = nn::Pool::create(pg::test::gpu());
    for (auto [cin, cout] : {std::pair<int64_t, int64_t>{16, 32}, {8, 16}, {3, 5}}) {
        const ConvCase c = conv_case(1500, 12, 3, true, cin, cout, 91);
        INFO("cin " << cin << ", cout " << cout);
        Tensor nbr = nn::upload_tensor(*pool, c.nbr, {c.P, c.T}, DType::I32);
        Tensor x = up(*pool, c.x, {c.P, cin}), w = up(*pool, c.w, {cout, c.T * cin}), dy = up(*pool, c.dy, {c.P, cout});
        vk::CommandList cmd(pool->context());
        const auto rules = nn::ops::build_rulebook(cmd, *pool, nbr);
        auto g = nn::grad::sparse_conv_backward(cmd, *pool, x, rules, w, dy);
        cmd.submit_and_wait();
        const auto want = gpu_conv(*pool, c, cin, cout);
        CHECK(same_bits(down(*pool, g.dx), want[0]));
        CHECK(same_bits(down(*pool, g.dw), want[1]));
        CHECK(same_bits(down(*pool, g.db), want[2]));
        const auto ref_g = gref::conv_backward(gref::to_double(c.x), c.nbr, gref::to_double(c.w), gref::to_double(c.dy),
                                               c.P, c.T, cin, cout);
        CHECK(gref::worst_error(down(*pool, g.dx), ref_g.dx, 1e-5) <= 1.0);
    }
}

TEST_CASE("submanifold maps are symmetric for distinct voxels only") {
    // The GPU neighbour map of distinct voxels (what voxelize yields) is symmetric ...
    auto pool = nn::Pool::create(pg::test::gpu());
    for (int kernel : {3, 5}) {
        const ref::Cloud cloud = ref::random_cloud(400, 3, 9, 61 + kernel, true);
        const int64_t n = int64_t(cloud.size()), T = int64_t(kernel) * kernel * kernel;
        Tensor grid = nn::upload_tensor(*pool, cloud.grid, {n, 3}, DType::I32);
        Tensor batch = nn::upload_tensor(*pool, cloud.batch, {n}, DType::I32);
        vk::CommandList cmd(pool->context());
        Tensor nbr = nn::ops::neighbor_map(cmd, *pool, grid, batch, kernel);
        cmd.submit_and_wait();
        CHECK(gref::symmetric_map(nn::download_tensor<int32_t>(pool->context(), nbr), n, T));
    }
    // ... and with a duplicated voxel it is not, and the mirrored dx is then wrong: the
    // assumption the conv backward documents.
    ConvCase c = conv_case(60, 4, 3, false, 3, 4, 71);
    REQUIRE_FALSE(gref::symmetric_map(c.nbr, c.P, c.T));
    const auto got = gpu_conv(*pool, c, 3, 4);
    const auto want = gref::conv_backward(gref::to_double(c.x), c.nbr, gref::to_double(c.w), gref::to_double(c.dy), c.P,
                                          c.T, 3, 4);
    CHECK(gref::worst_error(got[0], want.dx, 1e-5) > 1.0);
    CHECK(gref::worst_error_normwise(got[1], want.dw, 1e-5) <= 1.0);  // dw and db need no symmetry
}

TEST_CASE("linear and sparse_conv backward hold on both GEMM kernel families") {
    // dx runs through the forward's GEMMs; GPUs take the tiled kernels, CPU devices the lanes ones.
    auto pool = nn::Pool::create(pg::test::gpu());
    for (auto path : {nn::ops::GemmPath::Tiled, nn::ops::GemmPath::Lanes}) {
        nn::ops::set_gemm_path(path);
        INFO("path " << (path == nn::ops::GemmPath::Tiled ? "tiled" : "lanes"));
        check_linear(*pool, 130, 40, 72, 81);
        check_linear(*pool, 3, 5, 9, 82);
        check_conv(*pool, 200, 7, 3, 8, 16, 83);
        check_conv(*pool, 100, 6, 3, 3, 5, 84);
    }
    nn::ops::set_gemm_path(nn::ops::GemmPath::Auto);
}

TEST_CASE("linear and sparse_conv backward reject mismatched shapes") {
    auto pool = nn::Pool::create(pg::test::gpu());
    vk::CommandList cmd(pool->context());
    auto zeros = [&](std::vector<int64_t> shape) { return pool->empty(std::move(shape)); };
    CHECK_THROWS_AS(nn::grad::linear_backward(cmd, *pool, zeros({4, 3}), zeros({5, 3}), zeros({4, 6})),
                    std::invalid_argument);
    CHECK_THROWS_AS(nn::grad::linear_backward(cmd, *pool, zeros({4, 3}), zeros({5, 2}), zeros({4, 5})),
                    std::invalid_argument);
    Tensor nbr = pool->empty({4, 27}, DType::I32);
    CHECK_THROWS_AS(nn::grad::sparse_conv_backward(cmd, *pool, zeros({4, 3}), nbr, zeros({5, 27 * 2}), zeros({4, 5})),
                    std::invalid_argument);
    CHECK_THROWS_AS(nn::grad::sparse_conv_backward(cmd, *pool, zeros({6, 3}), nbr, zeros({5, 27 * 3}), zeros({6, 5})),
                    std::invalid_argument);  // the map must cover every voxel (submanifold: P rows)
}

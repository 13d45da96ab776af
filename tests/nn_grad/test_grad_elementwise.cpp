// Backward of GELU, add, row gathers (general, permutation, pooling clusters), add_gathered and
// the cluster max (nn/train/grad_ops.h): GPU == CPU reference, CPU reference == central finite
// differences, bit-identical reruns.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <random>
#include <vector>

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

Tensor up_i32(nn::Pool& pool, const std::vector<int32_t>& v) {
    return nn::upload_tensor(pool, v, {int64_t(v.size())}, DType::I32);
}



// For copies and routings, which do no arithmetic.
bool exact(const std::vector<float>& got, const gref::Vec& want) {
    if (got.size() != want.size()) return false;
    for (size_t i = 0; i < got.size(); ++i)
        if (double(got[i]) != want[i]) return false;
    return true;
}

std::vector<int32_t> random_index(size_t n, int32_t bound, uint32_t seed) {
    std::mt19937 rng(seed);
    std::vector<int32_t> v(n);
    for (auto& i : v) i = int32_t(rng() % uint32_t(bound));
    return v;
}

// Clusters of random codes (the pooling of a cloud of n points into about n / 4 clusters), as the
// reference holds them and as the GPU op returns them.
struct ClusterCase {
    ref::Clusters ref;
    nn::ops::Clusters gpu;
};

ClusterCase cluster_case(nn::Pool& pool, size_t n, uint32_t seed) {
    std::mt19937_64 rng(seed);
    std::vector<uint64_t> code(n);
    for (auto& c : code) c = rng() % std::max<uint64_t>(4 * (n / 4 + 1), 4);
    ClusterCase c;
    c.ref = ref::pool_clusters(code, 2);
    c.gpu = {up_i32(pool, c.ref.cluster), up_i32(pool, c.ref.members), up_i32(pool, c.ref.ptr), up_i32(pool, c.ref.head),
             int64_t(c.ref.head.size())};
    return c;
}

std::vector<float> gpu_gather_backward(nn::Pool& pool, const std::vector<float>& dy, const std::vector<int32_t>& idx,
                                       int64_t P, int64_t C) {
    // Uploads act at once: all of them before recording (see tensor.h).
    Tensor tidx = up_i32(pool, idx), tdy = up(pool, dy, {int64_t(idx.size()), C});
    vk::CommandList cmd(pool.context());
    const auto groups = nn::grad::group_rows(cmd, pool, tidx, P);
    Tensor dx = nn::grad::gather_rows_backward(cmd, pool, tdy, groups);
    cmd.submit_and_wait();
    CHECK(dx.shape == std::vector<int64_t>{P, C});
    return down(pool, dx);
}

void check_gather(nn::Pool& pool, size_t R, int64_t P, int64_t C, uint32_t seed) {
    INFO("R=" << R << " P=" << P << " C=" << C);
    const auto idx = random_index(R, int32_t(P), seed);
    const auto dy = ref::random_uniform(R * size_t(C), seed + 1);
    CHECK(gref::worst_error(gpu_gather_backward(pool, dy, idx, P, C),
                            gref::gather_rows_backward(gref::to_double(dy), idx, P, C), 1e-5) <= 1.0);
}

std::vector<float> gpu_segment_max_backward(nn::Pool& pool, const ClusterCase& c, const std::vector<float>& x,
                                            const std::vector<float>& dy, int64_t C) {
    const int64_t N = int64_t(c.ref.cluster.size());
    Tensor tx = up(pool, x, {N, C}), tdy = up(pool, dy, {c.gpu.count, C});
    vk::CommandList cmd(pool.context());
    Tensor dx = nn::grad::segment_max_backward(cmd, pool, tx, c.gpu, tdy);
    cmd.submit_and_wait();
    return down(pool, dx);
}

// Values on a coarse grid, so clusters often hold ties.
std::vector<float> tied_values(size_t n, uint32_t seed) {
    auto v = ref::random_uniform(n, seed, -1.0f, 1.0f);
    for (auto& x : v) x = std::round(x * 2.0f) / 2.0f;
    return v;
}

}  // namespace

TEST_CASE("gelu backward matches the CPU reference and finite differences") {
    auto pool = nn::Pool::create(pg::test::gpu());
    for (size_t n : {size_t(1), size_t(7), size_t(1000), size_t(65537)}) {
        INFO("n=" << n);
        auto x = ref::random_uniform(n, uint32_t(n), -6.0f, 6.0f);
        if (n >= 7) {
            const float ends[] = {-30.0f, -10.0f, -0.875f, 0.0f, 0.875f, 10.0f, 30.0f};  // tails, erf piece seams
            std::copy(std::begin(ends), std::end(ends), x.begin());
        }
        const auto dy = ref::random_uniform(n, uint32_t(n) + 1);
        Tensor tx = up(*pool, x, {int64_t(n)}), tdy = up(*pool, dy, {int64_t(n)});
        vk::CommandList cmd(pool->context());
        Tensor dx = nn::grad::gelu_backward(cmd, *pool, tx, tdy);
        cmd.submit_and_wait();
        CHECK(gref::worst_error(down(*pool, dx), gref::gelu_backward(gref::to_double(x), gref::to_double(dy)), 1e-5) <= 1.0);
    }
    const auto x = gref::to_double(ref::random_uniform(12, 5, -4.0f, 4.0f)), dy = gref::to_double(ref::random_uniform(12, 6));
    const auto num = gref::numeric_gradient([&](const gref::Vec& v) { return gref::dot(dy, gref::gelu_forward(v)); }, x);
    CHECK(gref::worst_error(gref::gelu_backward(x, dy), num, 1e-7) <= 1.0);
}

TEST_CASE("add backward passes dy to both operands") {
    auto pool = nn::Pool::create(pg::test::gpu());
    Tensor dy = up(*pool, {1.0f, 2.0f, 3.0f}, {3});
    const auto g = nn::grad::add_backward(dy);
    CHECK(down(*pool, g.da) == std::vector<float>{1.0f, 2.0f, 3.0f});
    CHECK(down(*pool, g.db) == std::vector<float>{1.0f, 2.0f, 3.0f});
}

TEST_CASE("gather_rows backward sums the rows of each target") {
    auto pool = nn::Pool::create(pg::test::gpu());
    check_gather(*pool, 1, 1, 1, 1);
    check_gather(*pool, 1, 5, 3, 2);         // one row, targets never gathered get 0
    check_gather(*pool, 1000, 300, 17, 3);   // repeats
    check_gather(*pool, 300, 1000, 8, 4);    // mostly untouched targets
    check_gather(*pool, 20000, 8192, 6, 5);  // an inverse map: points -> voxels
    // Indices outside [0, P) join no group.
    const std::vector<int32_t> idx{2, -1, 0, 5, 2, 7};
    const auto dy = ref::random_uniform(idx.size() * 2, 6);
    const auto got = gpu_gather_backward(*pool, dy, idx, 5, 2);
    gref::Vec want(10, 0.0);
    for (size_t r = 0; r < idx.size(); ++r)
        if (idx[r] >= 0 && idx[r] < 5)
            for (int c = 0; c < 2; ++c) want[size_t(idx[r] * 2 + c)] += dy[r * 2 + size_t(c)];
    CHECK(gref::worst_error(got, want, 1e-6) <= 1.0);
}

TEST_CASE("gather_rows backward through a permutation needs no sort") {
    auto pool = nn::Pool::create(pg::test::gpu());
    for (size_t R : {size_t(1), size_t(77), size_t(5000)}) {
        std::vector<int32_t> idx(R);
        std::iota(idx.begin(), idx.end(), 0);
        std::shuffle(idx.begin(), idx.end(), std::mt19937(uint32_t(R)));
        const auto dy = ref::random_uniform(R * 5, uint32_t(R) + 1);
        Tensor tdy = up(*pool, dy, {int64_t(R), 5}), tidx = up_i32(*pool, idx);
        vk::CommandList cmd(pool->context());
        Tensor dx = nn::grad::gather_rows_backward_permutation(cmd, *pool, tdy, tidx);
        cmd.submit_and_wait();
        CHECK(exact(down(*pool, dx), gref::gather_rows_backward(gref::to_double(dy), idx, int64_t(R), 5)));
    }
}

TEST_CASE("gather_rows and add_gathered backward references match finite differences") {
    const int64_t P = 4, C = 3;
    const std::vector<int32_t> idx{3, 0, 3, 3, 1};  // target 2 never gathered, 3 three times
    const auto x = gref::to_double(ref::random_uniform(size_t(P * C), 1));
    const auto a = gref::to_double(ref::random_uniform(idx.size() * size_t(C), 2));
    const auto dy = gref::to_double(ref::random_uniform(idx.size() * size_t(C), 3));
    const auto num_x =
        gref::numeric_gradient([&](const gref::Vec& v) { return gref::dot(dy, gref::gather_rows_forward(v, idx, C)); }, x);
    CHECK(gref::worst_error(gref::gather_rows_backward(dy, idx, P, C), num_x, 1e-7) <= 1.0);
    const auto g = gref::add_gathered_backward(dy, idx, P, C);
    auto loss = [&](const gref::Vec& aa, const gref::Vec& xx) { return gref::dot(dy, gref::add_gathered_forward(aa, xx, idx, C)); };
    CHECK(gref::worst_error(g.da, gref::numeric_gradient([&](const gref::Vec& v) { return loss(v, x); }, a), 1e-7) <= 1.0);
    CHECK(gref::worst_error(g.dx, gref::numeric_gradient([&](const gref::Vec& v) { return loss(a, v); }, x), 1e-7) <= 1.0);
}

TEST_CASE("add_gathered backward through pooling clusters equals the sorted grouping, bit for bit") {
    auto pool = nn::Pool::create(pg::test::gpu());
    for (size_t n : {size_t(1), size_t(50), size_t(9000)}) {
        INFO("n=" << n);
        const ClusterCase c = cluster_case(*pool, n, uint32_t(n));
        const int64_t C = 12, M = c.gpu.count;
        const auto dy = ref::random_uniform(n * size_t(C), uint32_t(n) + 3);
        Tensor tdy = up(*pool, dy, {int64_t(n), C});
        vk::CommandList cmd(pool->context());
        // Unpooling: y[point] = skip[point] + up[cluster[point]].
        const auto from_clusters = nn::grad::add_gathered_backward(cmd, *pool, tdy, nn::grad::group_rows(c.gpu));
        const auto sorted = nn::grad::add_gathered_backward(cmd, *pool, tdy,
                                                            nn::grad::group_rows(cmd, *pool, c.gpu.cluster, M));
        cmd.submit_and_wait();
        const auto want = gref::add_gathered_backward(gref::to_double(dy), c.ref.cluster, M, C);
        CHECK(exact(down(*pool, from_clusters.da), want.da));
        CHECK(gref::worst_error(down(*pool, from_clusters.dx), want.dx, 1e-5) <= 1.0);
        CHECK(same_bits(down(*pool, from_clusters.dx), down(*pool, sorted.dx)));
    }
}

TEST_CASE("gather_rows backward is bit-identical across runs") {
    auto pool = nn::Pool::create(pg::test::gpu());
    const auto idx = random_index(30000, 4000, 9);
    const auto dy = ref::random_uniform(idx.size() * 8, 10);
    CHECK(same_bits(gpu_gather_backward(*pool, dy, idx, 4000, 8), gpu_gather_backward(*pool, dy, idx, 4000, 8)));
}

TEST_CASE("segment_max backward routes dy to the max, the lowest index among ties") {
    auto pool = nn::Pool::create(pg::test::gpu());
    for (size_t n : {size_t(1), size_t(33), size_t(4000)}) {
        for (int64_t C : {int64_t(1), int64_t(16)}) {
            INFO("n=" << n << " C=" << C);
            const ClusterCase c = cluster_case(*pool, n, uint32_t(n + C));
            const auto x = tied_values(n * size_t(C), uint32_t(n) + 1);
            const auto dy = ref::random_uniform(size_t(c.gpu.count * C), uint32_t(n) + 2);
            const auto want = gref::segment_max_backward(gref::to_double(x), gref::to_double(dy), C, c.ref);
            const auto got = gpu_segment_max_backward(*pool, c, x, dy, C);
            CHECK(exact(got, want));
            CHECK(same_bits(got, gpu_segment_max_backward(*pool, c, x, dy, C)));
        }
    }
}

TEST_CASE("segment_max backward reference matches finite differences, ties included") {
    auto pool = nn::Pool::create(pg::test::gpu());
    const int64_t C = 3;
    const ClusterCase c = cluster_case(*pool, 24, 77);
    const auto x = gref::to_double(tied_values(24 * size_t(C), 78));
    const auto dy = gref::to_double(ref::random_uniform(c.ref.head.size() * size_t(C), 79));
    const auto g = gref::segment_max_backward(x, dy, C, c.ref);
    const auto num = gref::numeric_gradient(
        [&](const gref::Vec& v) { return gref::dot(dy, gref::segment_max_forward(v, C, c.ref)); }, x);
    // Off ties the max is differentiable: the gradients agree entry by entry. On a tie the max has
    // no gradient (central differences give each tied member dy/2: one side moves the max, the
    // other does not). There the check is the derivative along moving the whole tie together,
    // which is dy and must equal the gradient's sum over the tie, all of it on the lowest index.
    int ties = 0;
    for (size_t m = 0; m + 1 < c.ref.ptr.size(); ++m)
        for (int64_t ch = 0; ch < C; ++ch) {
            auto entry = [&](int32_t j) { return size_t(c.ref.members[size_t(j)] * C + ch); };
            double mx = -INFINITY;
            for (int32_t j = c.ref.ptr[m]; j < c.ref.ptr[m + 1]; ++j) mx = std::max(mx, x[entry(j)]);
            std::vector<size_t> tied;
            for (int32_t j = c.ref.ptr[m]; j < c.ref.ptr[m + 1]; ++j)
                if (x[entry(j)] == mx) tied.push_back(entry(j));
            if (tied.size() == 1) {
                for (int32_t j = c.ref.ptr[m]; j < c.ref.ptr[m + 1]; ++j)
                    CHECK(std::fabs(g[entry(j)] - num[entry(j)]) <= 1e-7 * (1 + std::fabs(num[entry(j)])));
                continue;
            }
            ++ties;
            const double d = dy[m * size_t(C) + size_t(ch)], eps = 1e-6;
            auto moved = [&](double by) {
                gref::Vec v = x;
                for (size_t i : tied) v[i] += by;
                return gref::dot(dy, gref::segment_max_forward(v, C, c.ref));
            };
            const double along = (moved(eps) - moved(-eps)) / (2 * eps);
            double sum_g = 0;
            for (size_t i : tied) {
                sum_g += g[i];
                CHECK(std::fabs(num[i] - d / 2) <= 1e-7 * (1 + std::fabs(d)));
            }
            CHECK(std::fabs(along - d) <= 1e-7 * (1 + std::fabs(d)));
            CHECK(std::fabs(sum_g - along) <= 1e-7 * (1 + std::fabs(d)));
            CHECK(g[*std::min_element(tied.begin(), tied.end())] == d);  // members ascending: lowest entry = lowest index
        }
    CHECK(ties > 0);  // the case exercises ties
}

TEST_CASE("pooling and unpooling backward work on the clusters pool_clusters builds") {
    auto pool = nn::Pool::create(pg::test::gpu());
    const size_t n = 3000;
    const int64_t C = 8;
    std::mt19937_64 rng(91);
    std::vector<uint64_t> code(n);
    for (auto& c : code) c = rng() % 4096;
    const ref::Clusters want_clusters = ref::pool_clusters(code, 3);
    const int64_t M = int64_t(want_clusters.head.size());
    const auto x = tied_values(n * size_t(C), 92);
    const auto dy_pool = ref::random_uniform(size_t(M * C), 93), dy_unpool = ref::random_uniform(n * size_t(C), 94);
    Tensor tcode = nn::upload_tensor(*pool, code, {int64_t(n)}, DType::U64), tx = up(*pool, x, {int64_t(n), C});
    Tensor tdy_pool = up(*pool, dy_pool, {M, C}), tdy_unpool = up(*pool, dy_unpool, {int64_t(n), C});
    vk::CommandList cmd(pool->context());
    const nn::ops::Clusters clusters = nn::ops::pool_clusters(cmd, *pool, tcode, 3);  // waits once
    REQUIRE(clusters.count == M);
    Tensor dx_pool = nn::grad::segment_max_backward(cmd, *pool, tx, clusters, tdy_pool);
    const auto unpool = nn::grad::add_gathered_backward(cmd, *pool, tdy_unpool, nn::grad::group_rows(clusters));
    cmd.submit_and_wait();
    CHECK(exact(down(*pool, dx_pool), gref::segment_max_backward(gref::to_double(x), gref::to_double(dy_pool), C,
                                                                 want_clusters)));
    CHECK(gref::worst_error(down(*pool, unpool.dx),
                            gref::gather_rows_backward(gref::to_double(dy_unpool), want_clusters.cluster, M, C), 1e-5) <= 1);
}

// Softmax cross-entropy (nn/train/grad_ops.h): loss and dlogits on the GPU == CPU reference,
// CPU dlogits == central finite differences of the CPU loss, ignored and bad labels,
// bit-identical reruns.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <stdexcept>
#include <vector>

#include "nn/train/grad_ops.h"
#include "tests/gpu_fixture.h"
#include "tests/nn_grad/grad_test_util.h"
#include "tests/reference/nn_dense_ref.h"
#include "tests/reference/nn_grad_ref.h"

using namespace pg;
using nn::DType;
using nn::Tensor;
namespace ref = pg::test::ref;
namespace gref = pg::test::ref::grad;
using pg::test::random_labels;

namespace {

struct GpuLoss {
    float loss;
    std::vector<float> dlogits;
    std::vector<uint32_t> info;
};

GpuLoss gpu_loss(nn::Pool& pool, const std::vector<float>& logits, const std::vector<int32_t>& labels, int64_t K,
                 int32_t ignore = -1) {
    const int64_t M = int64_t(labels.size());
    Tensor tl = nn::upload_tensor(pool, logits, {M, K}, DType::F32), tlab = nn::upload_tensor(pool, labels, {M}, DType::I32);
    vk::CommandList cmd(pool.context());
    auto ce = nn::grad::cross_entropy(cmd, pool, tl, tlab, ignore);
    cmd.submit_and_wait();
    CHECK(ce.dlogits.shape == std::vector<int64_t>{M, K});
    return {nn::download_tensor<float>(pool.context(), ce.loss)[0], nn::download_tensor<float>(pool.context(), ce.dlogits),
            nn::download_tensor<uint32_t>(pool.context(), ce.info)};
}

void check_loss(nn::Pool& pool, size_t M, int32_t K, double ignored, float spread, uint32_t seed) {
    INFO("M=" << M << " K=" << K << " ignored " << ignored << " spread " << spread);
    const auto logits = ref::random_uniform(M * size_t(K), seed, -spread, spread);
    const auto labels = random_labels(M, K, ignored, seed + 1);
    const auto got = gpu_loss(pool, logits, labels, K);
    const auto want = gref::cross_entropy(gref::to_double(logits), labels, int64_t(M), K, -1);
    CHECK(std::fabs(got.loss - want.loss) <= 1e-5 * (1 + std::fabs(want.loss)));
    CHECK(gref::worst_error(got.dlogits, want.dlogits, 1e-5) <= 1.0);
    CHECK(got.info[0] == uint32_t(want.counted));
    CHECK(got.info[1] == 0);
}

}  // namespace

TEST_CASE("cross_entropy matches the CPU reference, ignored rows included") {
    auto pool = nn::Pool::create(pg::test::gpu());
    check_loss(*pool, 1, 1, 0.0, 1.0f, 1);
    check_loss(*pool, 1, 2, 0.0, 1.0f, 2);
    check_loss(*pool, 7, 13, 0.3, 3.0f, 3);
    check_loss(*pool, 1000, 2, 0.1, 5.0f, 4);    // the interactive model: object / background
    check_loss(*pool, 8192, 20, 0.2, 8.0f, 5);
    check_loss(*pool, 300, 5, 0.0, 60.0f, 6);    // logits far apart: the max shift keeps exp finite
}

TEST_CASE("cross_entropy reference gradient matches finite differences") {
    const int64_t M = 6, K = 4;
    const auto logits = gref::to_double(ref::random_uniform(size_t(M * K), 11, -2.0f, 2.0f));
    const std::vector<int32_t> labels{0, -1, 3, 2, -1, 1};
    const auto want = gref::cross_entropy(logits, labels, M, K, -1);
    CHECK(want.counted == 4);
    const auto num = gref::numeric_gradient(
        [&](const gref::Vec& v) { return gref::cross_entropy(v, labels, M, K, -1).loss; }, logits);
    CHECK(gref::worst_error(want.dlogits, num, 1e-7) <= 1.0);
    for (int64_t k = 0; k < K; ++k) {  // ignored rows get no gradient
        CHECK(want.dlogits[size_t(1 * K + k)] == 0.0);
        CHECK(want.dlogits[size_t(4 * K + k)] == 0.0);
    }
}

TEST_CASE("cross_entropy skips and counts bad labels, and is 0 with no row counted") {
    auto pool = nn::Pool::create(pg::test::gpu());
    const auto logits = ref::random_uniform(5 * 3, 21);
    const std::vector<int32_t> labels{0, 3, -7, 2, 255};
    const auto got = gpu_loss(*pool, logits, labels, 3, 255);  // a custom ignore label
    const auto want = gref::cross_entropy(gref::to_double(logits), labels, 5, 3, 255);
    CHECK(got.info == std::vector<uint32_t>{2, 2});
    CHECK(want.bad == 2);
    CHECK(std::fabs(got.loss - want.loss) <= 1e-5 * (1 + std::fabs(want.loss)));
    CHECK(gref::worst_error(got.dlogits, want.dlogits, 1e-5) <= 1.0);

    const auto none = gpu_loss(*pool, logits, {-1, -1, -1, -1, -1}, 3);
    CHECK(none.loss == 0.0f);
    CHECK(none.info == std::vector<uint32_t>{0, 0});
    for (float d : none.dlogits) CHECK(d == 0.0f);
}

TEST_CASE("cross_entropy is bit-identical across runs") {
    auto pool = nn::Pool::create(pg::test::gpu());
    const auto logits = ref::random_uniform(20000 * 7, 31, -4.0f, 4.0f);
    const auto labels = random_labels(20000, 7, 0.1, 32);
    const auto a = gpu_loss(*pool, logits, labels, 7), b = gpu_loss(*pool, logits, labels, 7);
    CHECK(std::memcmp(&a.loss, &b.loss, sizeof(float)) == 0);
    CHECK(std::memcmp(a.dlogits.data(), b.dlogits.data(), a.dlogits.size() * sizeof(float)) == 0);
}

TEST_CASE("cross_entropy rejects mismatched shapes") {
    auto pool = nn::Pool::create(pg::test::gpu());
    vk::CommandList cmd(pool->context());
    CHECK_THROWS_AS(nn::grad::cross_entropy(cmd, *pool, pool->empty({4, 3}), pool->empty({5}, DType::I32)),
                    std::invalid_argument);
    CHECK_THROWS_AS(nn::grad::cross_entropy(cmd, *pool, pool->empty({4, 3}), pool->empty({4}, DType::F32)),
                    std::invalid_argument);
}

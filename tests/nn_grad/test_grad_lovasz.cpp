// Lovasz-softmax loss (nn/train/grad_ops.h): GPU loss and dlogits == CPU reference, CPU dlogits ==
// central finite differences of the CPU loss, hard predictions give 1 - IoU, ignored rows,
// the weight, bit-identical reruns.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numeric>
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

// Two-class logits whose errors are far apart (>= 1 / 3M): the GPU's float errors sort exactly
// as the reference's doubles. p_1 of row i is (perm[i] + 1/3) / M, so no p equals another's 1 - p.
std::vector<float> separated_logits(size_t M, uint32_t seed) {
    std::vector<size_t> perm(M);
    std::iota(perm.begin(), perm.end(), size_t(0));
    std::shuffle(perm.begin(), perm.end(), std::mt19937(seed));
    std::vector<float> v(2 * M);
    for (size_t i = 0; i < M; ++i) {
        const double p = (double(perm[i]) + 1.0 / 3.0) / double(M);
        v[2 * i] = 0.0f;
        v[2 * i + 1] = float(std::log(p / (1.0 - p)));
    }
    return v;
}

struct GpuLovasz {
    float loss;
    std::vector<float> dlogits;
};

GpuLovasz gpu_lovasz(nn::Pool& pool, const std::vector<float>& logits, const std::vector<int32_t>& labels, int64_t K,
                     float weight = 1.0f, int32_t ignore = -1) {
    const int64_t M = int64_t(labels.size());
    Tensor tl = nn::upload_tensor(pool, logits, {M, K}, DType::F32), tlab = nn::upload_tensor(pool, labels, {M}, DType::I32);
    vk::CommandList cmd(pool.context());
    auto lv = nn::grad::lovasz_softmax(cmd, pool, tl, tlab, ignore, weight);
    cmd.submit_and_wait();
    CHECK(lv.dlogits.shape == std::vector<int64_t>{M, K});
    return {nn::download_tensor<float>(pool.context(), lv.loss)[0], nn::download_tensor<float>(pool.context(), lv.dlogits)};
}

void check_against_reference(nn::Pool& pool, const std::vector<float>& logits, const std::vector<int32_t>& labels,
                             int64_t K) {
    const int64_t M = int64_t(labels.size());
    INFO("M=" << M << " K=" << K);
    const auto got = gpu_lovasz(pool, logits, labels, K);
    const auto want = gref::lovasz_softmax(gref::to_double(logits), labels, M, K, -1);
    CHECK(std::fabs(got.loss - want.loss) <= 1e-5 * (1 + std::fabs(want.loss)));
    CHECK(gref::worst_error(got.dlogits, want.dlogits, 1e-5) <= 1.0);
}

// Mean over the classes present of 1 - IoU(argmax == c, label == c), over counted rows.
double jaccard_loss_of_argmax(const std::vector<float>& logits, const std::vector<int32_t>& labels, int64_t K) {
    double sum = 0;
    int present = 0;
    for (int64_t c = 0; c < K; ++c) {
        int64_t inter = 0, uni = 0, gt = 0;
        for (size_t m = 0; m < labels.size(); ++m) {
            if (labels[m] < 0) continue;
            const float* l = &logits[m * size_t(K)];
            const bool pred = std::max_element(l, l + K) - l == c, is = labels[m] == c;
            inter += pred && is;
            uni += pred || is;
            gt += is;
        }
        if (gt == 0) continue;
        ++present;
        sum += 1.0 - double(inter) / double(uni);
    }
    return present ? sum / present : 0.0;
}

}  // namespace

TEST_CASE("lovasz_softmax matches the CPU reference") {
    auto pool = nn::Pool::create(pg::test::gpu());
    check_against_reference(*pool, separated_logits(1, 1), {1}, 2);
    check_against_reference(*pool, separated_logits(1000, 2), random_labels(1000, 2, 0.1, 3), 2);  // object / background
    check_against_reference(*pool, separated_logits(8192, 4), random_labels(8192, 2, 0.0, 5), 2);
    check_against_reference(*pool, ref::random_uniform(40 * 3, 6, -3.0f, 3.0f), random_labels(40, 3, 0.2, 7), 3);
    check_against_reference(*pool, ref::random_uniform(25 * 5, 8, -2.0f, 2.0f), random_labels(25, 4, 0.0, 9), 5);
}

TEST_CASE("lovasz_softmax reference gradient matches finite differences") {
    const int64_t M = 8, K = 3;
    const auto logits = gref::to_double(ref::random_uniform(size_t(M * K), 41, -2.0f, 2.0f));
    const std::vector<int32_t> labels{0, 2, -1, 2, 0, 0, 2, 1};
    const auto want = gref::lovasz_softmax(logits, labels, M, K, -1);
    const auto num = gref::numeric_gradient(
        [&](const gref::Vec& v) { return gref::lovasz_softmax(v, labels, M, K, -1).loss; }, logits);
    CHECK(gref::worst_error(want.dlogits, num, 1e-6) <= 1.0);
    for (int64_t k = 0; k < K; ++k) CHECK(want.dlogits[size_t(2 * K + k)] == 0.0);  // the ignored row
}

TEST_CASE("lovasz_softmax of confident predictions is the Jaccard loss of the argmax") {
    auto pool = nn::Pool::create(pg::test::gpu());
    // Logits 40 apart: probabilities are exactly 0 and 1 in float, errors 0 or 1, and the Lovasz
    // extension at a 0/1 error vector is the set function itself, 1 - IoU.
    const size_t M = 500;
    const int64_t K = 3;
    const auto labels = random_labels(M, int32_t(K), 0.1, 51);
    std::mt19937 rng(52);
    std::vector<float> logits(M * size_t(K), -20.0f);
    for (size_t m = 0; m < M; ++m) {
        const int64_t truth = labels[m] < 0 ? 0 : labels[m];
        const int64_t pred = rng() % 4 == 0 ? int64_t(rng() % uint32_t(K)) : truth;  // ~1/4 guessed
        logits[m * size_t(K) + size_t(pred)] = 20.0f;
    }
    const double want = jaccard_loss_of_argmax(logits, labels, K);
    CHECK(want > 0.1);
    CHECK(gpu_lovasz(*pool, logits, labels, K).loss == Approx(want).epsilon(1e-5));
    CHECK(gref::lovasz_softmax(gref::to_double(logits), labels, int64_t(M), K, -1).loss == Approx(want).epsilon(1e-9));
}

TEST_CASE("lovasz_softmax leaves out ignored rows, scales by its weight, and is bit-identical across runs") {
    auto pool = nn::Pool::create(pg::test::gpu());
    const auto logits = separated_logits(3000, 61);
    auto labels = random_labels(3000, 2, 0.0, 62);
    const auto one = gpu_lovasz(*pool, logits, labels, 2);
    CHECK(one.loss > 0.0f);
    const auto half = gpu_lovasz(*pool, logits, labels, 2, 0.5f);
    CHECK(half.loss == Approx(0.5 * one.loss).epsilon(1e-6));
    gref::Vec halved = gref::to_double(one.dlogits);
    for (double& d : halved) d *= 0.5;
    CHECK(gref::worst_error(half.dlogits, halved, 1e-6) <= 1.0);
    const auto again = gpu_lovasz(*pool, logits, labels, 2);
    CHECK(std::memcmp(&again.loss, &one.loss, sizeof(float)) == 0);
    CHECK(std::memcmp(again.dlogits.data(), one.dlogits.data(), one.dlogits.size() * sizeof(float)) == 0);

    // Ignored and out-of-range rows: as if they were not there, with no gradient.
    for (size_t m = 0; m < labels.size(); m += 3) labels[m] = m % 2 ? -1 : 7;
    const auto part = gpu_lovasz(*pool, logits, labels, 2);
    std::vector<float> kept_logits;
    std::vector<int32_t> kept_labels;
    for (size_t m = 0; m < labels.size(); ++m) {
        if (m % 3 == 0) {
            CHECK(part.dlogits[2 * m] == 0.0f);
            CHECK(part.dlogits[2 * m + 1] == 0.0f);
            continue;
        }
        kept_logits.insert(kept_logits.end(), {logits[2 * m], logits[2 * m + 1]});
        kept_labels.push_back(labels[m]);
    }
    CHECK(part.loss == Approx(gpu_lovasz(*pool, kept_logits, kept_labels, 2).loss).epsilon(1e-6));

    const auto none = gpu_lovasz(*pool, logits, std::vector<int32_t>(3000, -1), 2);
    CHECK(none.loss == 0.0f);
    CHECK(std::all_of(none.dlogits.begin(), none.dlogits.end(), [](float d) { return d == 0.0f; }));
}

TEST_CASE("lovasz_softmax rejects mismatched shapes") {
    auto pool = nn::Pool::create(pg::test::gpu());
    vk::CommandList cmd(pool->context());
    CHECK_THROWS_AS(nn::grad::lovasz_softmax(cmd, *pool, pool->empty({4, 2}), pool->empty({5}, DType::I32)),
                    std::invalid_argument);
    CHECK_THROWS_AS(nn::grad::lovasz_softmax(cmd, *pool, pool->empty({4, 2}), pool->empty({4}, DType::F32)),
                    std::invalid_argument);
}

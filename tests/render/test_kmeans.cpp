// GPU k-means (engine/compress/kmeans) against the CPU reference: the assignment pass picks the
// reference's nearest centroid, Lloyd steps match a CPU run of the same steps, the same seed
// gives the same bytes, and the 1-D codebook is ascending and tight.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include "engine/compress/kmeans.h"
#include "tests/gpu_fixture.h"
#include "tests/reference/kmeans_reference.h"

namespace {

// n points around `clusters` well-separated centres (spread 0.01, centres >= ~1 apart).
std::vector<float> blobs(size_t n, size_t dims, size_t clusters, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> centre(-20.0f, 20.0f);
    std::normal_distribution<float> noise(0.0f, 0.01f);
    std::vector<float> c(clusters * dims), p(n * dims);
    for (auto& v : c) v = centre(rng);
    for (size_t i = 0; i < n; ++i)
        for (size_t d = 0; d < dims; ++d) p[i * dims + d] = c[(i % clusters) * dims + d] + noise(rng);
    return p;
}

}  // namespace

TEST_CASE("kmeans: the GPU assignment and Lloyd steps match the CPU reference") {
    auto& ctx = pg::test::gpu();
    for (size_t dims : {1u, 9u, 45u}) {
        INFO("dims " << dims);
        const size_t n = 3000, k = 40;
        const auto points = blobs(n, dims, 25, dims);
        // One step against the CPU's step from the same start (iterations 0 gives the start): the
        // same labels, means within float rounding (the GPU sums in float with compensation).
        const auto start = pg::compress::kmeans(ctx, points, dims, k, 0, 7);
        CHECK(start.labels == pg::ref::nearest_centroids(points, start.centroids, dims));
        const auto one = pg::compress::kmeans(ctx, points, dims, k, 1, 7);
        std::vector<float> centroids = start.centroids;
        pg::compress::move_centroids(points, dims, start.labels, centroids);
        double worst = 0;
        for (size_t i = 0; i < centroids.size(); ++i)
            worst = std::max(worst, double(std::abs(centroids[i] - one.centroids[i])) / (1.0 + std::abs(centroids[i])));
        CHECK(worst < 1e-6);
        CHECK(one.labels == pg::ref::nearest_centroids(points, one.centroids, dims));
        // More steps: labels stay the nearest of the returned centroids, and the error only falls
        // (several centroids may share a blob, so later steps may part from the CPU's at near-ties).
        const auto four = pg::compress::kmeans(ctx, points, dims, k, 4, 7);
        REQUIRE(four.centroids.size() == k * dims);
        REQUIRE(four.labels.size() == n);
        CHECK(four.labels == pg::ref::nearest_centroids(points, four.centroids, dims));
        const double e0 = pg::ref::clustering_error(points, start.centroids, start.labels, dims);
        const double e1 = pg::ref::clustering_error(points, one.centroids, one.labels, dims);
        const double e4 = pg::ref::clustering_error(points, four.centroids, four.labels, dims);
        CHECK(e1 <= e0);
        CHECK(e4 <= e1 * (1 + 1e-6));
    }
}

TEST_CASE("kmeans: the same seed gives the same bytes, k >= n gives each point its own cluster") {
    auto& ctx = pg::test::gpu();
    const auto points = blobs(5000, 9, 300, 3);
    const auto a = pg::compress::kmeans(ctx, points, 9, 256, 3, 11);
    const auto b = pg::compress::kmeans(ctx, points, 9, 256, 3, 11);
    CHECK(a.centroids == b.centroids);
    CHECK(a.labels == b.labels);
    const auto own = pg::compress::kmeans(ctx, std::vector<float>(points.begin(), points.begin() + 9 * 10), 9, 16, 3, 1);
    for (uint32_t i = 0; i < 10; ++i) CHECK(own.labels[i] == i);
    CHECK(std::equal(own.centroids.begin() + 15 * 9, own.centroids.end(), points.begin() + 9 * 9));
}

TEST_CASE("kmeans: a 1-D codebook is ascending and fits a skewed distribution") {
    auto& ctx = pg::test::gpu();
    std::mt19937_64 rng(5);
    std::lognormal_distribution<float> skewed(0.0f, 1.0f);
    std::vector<float> values(60000);
    for (auto& v : values) v = std::log(skewed(rng)) * 2.0f - 4.0f;  // log-scales: normal, long tails
    const auto book = pg::compress::codebook_1d(ctx, values, 256, 10);
    REQUIRE(book.centroids.size() == 256);
    CHECK(std::is_sorted(book.centroids.begin(), book.centroids.end()));
    CHECK(book.labels == pg::ref::nearest_centroids(values, book.centroids, 1));
    // Better than a uniform 8-bit grid over the range (whose error is step / sqrt(12)).
    const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
    const double rms = std::sqrt(pg::ref::clustering_error(values, book.centroids, book.labels, 1) / double(values.size()));
    CHECK(rms < 0.9 * (*hi - *lo) / 255.0 / std::sqrt(12.0));
}

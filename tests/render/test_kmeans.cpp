// GPU k-means (engine/compress/kmeans, lloyd) against the CPU reference: each Lloyd step's
// labels and means, whole runs (the same error), the windowed update, the same bytes on a second
// run, and the 1-D codebook's error on skewed values.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <stdexcept>

#include "engine/compress/kmeans.h"
#include "engine/compress/lloyd.h"
#include "tests/gpu_fixture.h"
#include "tests/reference/kmeans_reference.h"

namespace {

// n points around `blobs` centres in [-1, 1]^dims (spread 0.01): far apart against the spread,
// so no point sits within float rounding of two centroids.
std::vector<float> blobs(size_t n, size_t dims, size_t blobs, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> centre(-1.0f, 1.0f);
    std::normal_distribution<float> noise(0.0f, 0.01f);
    std::vector<float> c(blobs * dims), p(n * dims);
    for (auto& v : c) v = centre(rng);
    for (size_t i = 0; i < n; ++i)
        for (size_t d = 0; d < dims; ++d) p[i * dims + d] = c[(i * 7919 % blobs) * dims + d] + noise(rng);
    return p;
}

// Largest difference of two centroid sets, relative to 1 + |value|.
double centroid_gap(const std::vector<float>& a, const std::vector<float>& b) {
    REQUIRE(a.size() == b.size());
    double worst = 0;
    for (size_t i = 0; i < a.size(); ++i)
        worst = std::max(worst, std::abs(double(a[i]) - b[i]) / (1.0 + std::abs(double(b[i]))));
    return worst;
}

size_t mismatches(const std::vector<uint32_t>& a, const std::vector<uint32_t>& b) {
    REQUIRE(a.size() == b.size());
    size_t m = 0;
    for (size_t i = 0; i < a.size(); ++i) m += a[i] != b[i];
    return m;
}

bool same_bytes(const pg::compress::Clusters& a, const pg::compress::Clusters& b) {
    return a.centroids.size() == b.centroids.size() && a.labels.size() == b.labels.size() &&
           std::memcmp(a.centroids.data(), b.centroids.data(), a.centroids.size() * sizeof(float)) == 0 &&
           std::memcmp(a.labels.data(), b.labels.data(), a.labels.size() * sizeof(uint32_t)) == 0;
}

}  // namespace

TEST_CASE("kmeans: each GPU Lloyd step matches the CPU reference's") {
    auto& ctx = pg::test::gpu();
    for (size_t dims : {1u, 2u, 9u, 24u, 45u}) {  // 2 runs padded to the 3-float kernel
        INFO("dims " << dims);
        const size_t n = 2000, k = 40;
        const auto points = blobs(n, dims, 25, dims);
        std::vector<float> centroids = pg::ref::kmeans_start(points, dims, k, 7);
        for (int step = 0; step < 3; ++step) {
            INFO("step " << step);
            // One step on each side from the same centroids: the same assignment, then means
            // within float rounding (the GPU sums in float with compensation, the CPU in double),
            // then the GPU's labels are the nearest of its own centroids.
            const auto labels = pg::ref::nearest_centroids(points, centroids, dims);
            CHECK(pg::compress::lloyd(ctx, points, dims, centroids, 0).labels == labels);
            const auto gpu = pg::compress::lloyd(ctx, points, dims, centroids, 1);
            pg::ref::move_centroids(points, dims, labels, centroids);
            CHECK(centroid_gap(gpu.centroids, centroids) < 1e-6);
            CHECK(gpu.labels == pg::ref::nearest_centroids(points, gpu.centroids, dims));
            centroids = gpu.centroids;
        }
    }
}

TEST_CASE("kmeans: whole runs match the CPU reference, k >= n gives each point its own cluster") {
    auto& ctx = pg::test::gpu();
    for (size_t dims : {1u, 9u, 45u}) {
        INFO("dims " << dims);
        const size_t n = 3000;
        const auto points = blobs(n, dims, 60, 100 + dims);
        for (size_t k : {size_t(20), size_t(97)}) {
            INFO("k " << k);
            const auto gpu = pg::compress::kmeans(ctx, points, dims, k, 8, 3);
            const auto cpu = pg::ref::kmeans(points, dims, k, 8, 3);
            REQUIRE(gpu.centroids.size() == k * dims);
            // Float and double means may part at a near-tie late on; the clustering's error may not.
            const double e_gpu = pg::ref::clustering_error(points, gpu.centroids, gpu.labels, dims);
            const double e_cpu = pg::ref::clustering_error(points, cpu.centroids, cpu.labels, dims);
            CHECK(std::abs(e_gpu - e_cpu) <= 1e-4 * e_cpu);
            CHECK(mismatches(gpu.labels, cpu.labels) <= n / 1000);
            CHECK(gpu.labels == pg::ref::nearest_centroids(points, gpu.centroids, dims));
        }
        for (size_t k : {n, n + 5}) {
            const auto own = pg::compress::kmeans(ctx, points, dims, k, 8, 3);
            const auto cpu = pg::ref::kmeans(points, dims, k, 8, 3);
            CHECK(own.labels == cpu.labels);
            CHECK(own.centroids == cpu.centroids);
            CHECK(std::equal(own.centroids.end() - long(dims), own.centroids.end(), points.end() - long(dims)));
        }
    }
}

TEST_CASE("kmeans: the windowed update matches the CPU reference") {
    // Windows of 8192 points and clusters of thousands: runs cross the update's 1024-member
    // chunks (heads and tails) and windows (the running sums).
    auto& ctx = pg::test::gpu();
    const size_t n = 20000, dims = 2;
    const auto points = blobs(n, dims, 6, 42);
    for (size_t k : {size_t(1), size_t(6)}) {
        INFO("k " << k);
        const auto start = pg::ref::kmeans_start(points, dims, k, 9);
        const auto cpu = pg::ref::lloyd(points, dims, start, 4);
        const auto windowed = pg::compress::lloyd(ctx, points, dims, start, 4, 8192);
        const auto whole = pg::compress::lloyd(ctx, points, dims, start, 4);
        CHECK(centroid_gap(windowed.centroids, cpu.centroids) < 1e-6);
        CHECK(centroid_gap(whole.centroids, cpu.centroids) < 1e-6);
        CHECK(windowed.labels == cpu.labels);
        CHECK(whole.labels == cpu.labels);
        CHECK(same_bytes(windowed, pg::compress::lloyd(ctx, points, dims, start, 4, 8192)));
    }
}

TEST_CASE("kmeans: ties go to the lower index, an empty cluster keeps its centroid") {
    // 4 distinct points, 50 copies each: the 12 starting centroids repeat some of them, so the
    // distances tie exactly; the later copy of a centroid never gets a point and stays put.
    auto& ctx = pg::test::gpu();
    for (size_t dims : {1u, 9u}) {
        INFO("dims " << dims);
        std::vector<float> points;
        for (size_t i = 0; i < 200; ++i)
            for (size_t d = 0; d < dims; ++d) points.push_back(float((i % 4) * 3 + d));
        const auto gpu = pg::compress::kmeans(ctx, points, dims, 12, 3, 5);
        const auto cpu = pg::ref::kmeans(points, dims, 12, 3, 5);
        CHECK(gpu.labels == cpu.labels);
        CHECK(centroid_gap(gpu.centroids, cpu.centroids) < 1e-6);
        const auto start = pg::ref::kmeans_start(points, dims, 12, 5);
        size_t kept = 0;
        for (size_t c = 0; c < 12; ++c)
            if (std::find(cpu.labels.begin(), cpu.labels.end(), uint32_t(c)) == cpu.labels.end())
                kept += std::equal(start.begin() + long(c * dims), start.begin() + long((c + 1) * dims),
                                   gpu.centroids.begin() + long(c * dims));
        CHECK(kept == 8);  // 12 centroids, 4 distinct points
    }
}

TEST_CASE("kmeans: the same input and seed give the same bytes") {
    auto& ctx = pg::test::gpu();
    std::mt19937_64 rng(3);
    std::normal_distribution<float> g(0.0f, 1.0f);
    std::vector<float> points(20000 * 9);  // no clusters at all: many near-ties, many moves
    for (auto& v : points) v = g(rng);
    const auto a = pg::compress::kmeans(ctx, points, 9, 300, 4, 11);
    const auto b = pg::compress::kmeans(ctx, points, 9, 300, 4, 11);
    CHECK(same_bytes(a, b));
    CHECK(!same_bytes(a, pg::compress::kmeans(ctx, points, 9, 300, 4, 12)));
}

TEST_CASE("kmeans: a 1-D codebook is ascending and fits a skewed distribution") {
    auto& ctx = pg::test::gpu();
    std::mt19937_64 rng(5);
    std::lognormal_distribution<float> skewed(0.0f, 1.0f);
    std::vector<float> values(60000);
    for (auto& v : values) v = skewed(rng);
    const auto book = pg::compress::codebook_1d(ctx, values, 256, 10);
    REQUIRE(book.centroids.size() == 256);
    CHECK(std::is_sorted(book.centroids.begin(), book.centroids.end()));
    CHECK(mismatches(book.labels, pg::ref::nearest_centroids(values, book.centroids, 1)) <= values.size() / 10000);
    const double mse = pg::ref::clustering_error(values, book.centroids, book.labels, 1) / double(values.size());
    const auto same = pg::ref::codebook_1d(values, pg::ref::codebook_start(values, 256), 10);
    const auto quantiles = pg::ref::codebook_1d(values, pg::ref::quantile_start(values, 256), 10);
    const double mse_same = pg::ref::clustering_error(values, same.centroids, same.labels, 1) / double(values.size());
    const double mse_quantiles =
        pg::ref::clustering_error(values, quantiles.centroids, quantiles.labels, 1) / double(values.size());
    INFO("mse " << mse << ", CPU from the same start " << mse_same << ", CPU from quantiles " << mse_quantiles);
    CHECK(mse <= 1.01 * mse_same);
    CHECK(mse <= mse_quantiles);
}

TEST_CASE("kmeans: bad arguments are refused") {
    auto& ctx = pg::test::gpu();
    const std::vector<float> points(90, 1.0f);
    CHECK_THROWS_AS(pg::compress::kmeans(ctx, points, 0, 4, 1, 1), std::invalid_argument);
    CHECK_THROWS_AS(pg::compress::kmeans(ctx, std::vector<float>(46 * 4), 46, 2, 1, 1), std::invalid_argument);
    CHECK_THROWS_AS(pg::compress::kmeans(ctx, points, 7, 4, 1, 1), std::invalid_argument);
    CHECK_THROWS_AS(pg::compress::kmeans(ctx, points, 9, 0, 1, 1), std::invalid_argument);
    CHECK_THROWS_AS(pg::compress::codebook_1d(ctx, {1.0f, NAN}, 256, 1), std::invalid_argument);
}

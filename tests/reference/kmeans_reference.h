#pragma once
// CPU reference of engine/compress/kmeans: plain Lloyd's k-means in double, written for
// clarity. The same starts (the seeded partial Fisher-Yates pick, the 1-D codebook's
// p^(1/3) levels), nearest centroid by squared distance with ties to the lower index, means in
// double, an empty cluster keeps its centroid, labels from an assignment after the last step.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace pg::ref {

struct KmeansResult {
    std::vector<float> centroids;  // k * dims
    std::vector<uint32_t> labels;  // one per point
};

// The k starting centroids of kmeans(): the first k of a partial Fisher-Yates shuffle of the
// point indices driven by std::mt19937_64(seed) (k < n).
std::vector<float> kmeans_start(const std::vector<float>& points, size_t dims, size_t k, uint64_t seed);
std::vector<uint32_t> nearest_centroids(const std::vector<float>& points, const std::vector<float>& centroids,
                                        size_t dims);
// One update: each centroid the mean of its points, an empty one unchanged.
void move_centroids(const std::vector<float>& points, size_t dims, const std::vector<uint32_t>& labels,
                    std::vector<float>& centroids);
// `iterations` steps from `centroids`.
KmeansResult lloyd(const std::vector<float>& points, size_t dims, std::vector<float> centroids, int iterations);
KmeansResult kmeans(const std::vector<float>& points, size_t dims, size_t k, int iterations, uint64_t seed);

// 1-D codebook starts: codebook_1d's p^(1/3) levels, and levels at the quantiles (2i+1)/(2k) of
// the sorted values (a plain start, the yardstick the codebook must not lose to).
std::vector<float> codebook_start(const std::vector<float>& values, size_t k);
std::vector<float> quantile_start(const std::vector<float>& values, size_t k);
// Lloyd's from `start`, centroids sorted ascending, labels into them.
KmeansResult codebook_1d(const std::vector<float>& values, std::vector<float> start, int iterations);

// Sum of squared distances of the points to their labels' centroids.
double clustering_error(const std::vector<float>& points, const std::vector<float>& centroids,
                        const std::vector<uint32_t>& labels, size_t dims);

}  // namespace pg::ref

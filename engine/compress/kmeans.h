#pragma once
// k-means on the GPU, for the SOG writer's SH palette (up to 65536 centroids of 9-45 floats) and
// its 256-entry codebooks. Each Lloyd step is compute passes (engine/compress/lloyd.h): the
// assignment compares points with blocks of centroids, the update sorts each window of points
// by label and sums every cluster's members in point order. No atomics and a fixed order: the
// same input and seed give the same bytes on every run of a device.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/vk/context.h"

namespace pg::compress {

struct Clusters {
    std::vector<float> centroids;  // k * dims, row-major
    std::vector<uint32_t> labels;  // one per point: index of its nearest centroid
};

constexpr size_t kMaxKmeansDims = 45;

// Lloyd's k-means of n points (row-major n * dims floats) into k clusters on the GPU: every
// iteration is an assignment pass (each point's nearest centroid, ties to the lower index) and
// an update pass (each centroid the mean of its points; an empty cluster keeps its centroid).
// Initial centroids: k distinct points, the first k of a partial Fisher-Yates shuffle of the
// indices 0..n-1 (for c = 0..k-1 swap c with c + mt19937_64(seed)() % (n - c)). k >= n gives
// each point its own cluster (centroids = points, padded by repeating the last point). Labels
// are final (an assignment pass after the last update).
Clusters kmeans(vk::Context& ctx, const std::vector<float>& points, size_t dims, size_t k, int iterations,
                uint64_t seed);

// 1-D codebook of k (256) ascending centroids for the pooled values, by the same passes; labels
// index the codebook. Lloyd's is started where a mean-squared-error quantiser puts its levels
// (density ∝ p^(1/3), Panter-Dite), read off a 4096-bin histogram of the value range: levels at
// quantiles of the values instead crowd the dense middle and starve the tails, 7-40x the error
// after 10 steps on skewed data, and a spike of equal values (zero SH) turns them into duplicates.
Clusters codebook_1d(vk::Context& ctx, const std::vector<float>& values, size_t k, int iterations);

}  // namespace pg::compress

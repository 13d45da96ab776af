#pragma once
// k-means on the GPU, for the SOG writer's SH palette (up to 65536 centroids of 9-45 floats) and
// its 256-entry codebooks. A Lloyd step is compute passes: compress/kmeans_assign gives every
// point its nearest centroid (n * k * dims, the whole cost; centroids tiled through shared
// memory, points in windows so any count fits the largest binding); a stable radix sort by label
// lists each cluster's members in point order, compress/kmeans_bounds finds their runs and
// compress/kmeans_update takes the means with compensated sums. No atomics and a fixed order:
// the same input and seed give the same bytes on every run. When the points pass one binding
// (millions at SH 3 on lavapipe) the means are taken on the host instead (move_centroids).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/vk/context.h"

namespace pg::compress {

struct Clusters {
    std::vector<float> centroids;  // k * dims, row-major
    std::vector<uint32_t> labels;  // one per point: its nearest centroid
};

constexpr size_t kMaxKmeansDims = 48;

// Lloyd's k-means of n points (row-major n * dims floats) into k clusters: k distinct points
// picked by a seeded PRNG to start, `iterations` steps (an empty cluster keeps its centroid),
// final labels from one more assignment. k >= n gives each point its own cluster (the last
// point repeated to fill k).
Clusters kmeans(vk::Context& ctx, const std::vector<float>& points, size_t dims, size_t k, int iterations,
                uint64_t seed);

// 1-D codebook: k ascending centroids for the pooled values: k-means started where a
// mean-squared-error quantiser puts its levels (density ∝ p^(1/3)); labels index the codebook.
Clusters codebook_1d(vk::Context& ctx, const std::vector<float>& values, size_t k, int iterations);

// A Lloyd step's update on the host (the fallback above, and the tests' reference): each centroid
// becomes the mean (in double) of its points; an empty cluster keeps its centroid.
void move_centroids(const std::vector<float>& points, size_t dims, const std::vector<uint32_t>& labels,
                    std::vector<float>& centroids);

}  // namespace pg::compress

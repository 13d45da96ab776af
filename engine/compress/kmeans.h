#pragma once
// k-means on the GPU, for the SOG writer's SH palette (up to 65536 centroids of 9-45 floats) and
// its 256-entry codebooks. Each Lloyd step assigns every point its nearest centroid in a compute
// pass (compress/kmeans_assign: n * k * dims, the whole cost), then moves each centroid to the
// mean of its points on the host in double precision, in point order (n * dims adds), so the
// result is the same bytes on every run. Points are uploaded once and assigned in windows, so
// any count fits the device's largest binding.
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

// The host half of a Lloyd step, shared with the tests' reference: each centroid becomes the
// mean (in double) of its points; an empty cluster keeps its centroid.
void move_centroids(const std::vector<float>& points, size_t dims, const std::vector<uint32_t>& labels,
                    std::vector<float>& centroids);

}  // namespace pg::compress

#pragma once
// Writing PlayCanvas SOG: bundled (.sog zip), version 2, lossless WebP, as splat-transform lays
// it out, so PlayCanvas, SuperSplat and splat-transform read it. The clustering (256-entry
// codebooks, the SH palette's k-means) is passed in: the engine runs it on the GPU, the tests
// can pass a CPU one; dataset stays free of Vulkan.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <vector>

#include "dataset/gaussian_cloud.h"

namespace pg::data {

struct SogClusters {
    std::vector<float> centroids;  // k * dims, row-major
    std::vector<uint32_t> labels;  // one per point
};

struct SogQuantizer {
    // 256 ascending centroids for pooled scalar values; labels index them.
    std::function<SogClusters(const std::vector<float>& values)> codebook;
    // k-means of n points of `dims` floats (row-major) into k clusters.
    std::function<SogClusters(const std::vector<float>& points, size_t dims, size_t k)> kmeans;
};

// Palette entries for n Gaussians, as splat-transform sizes it: 1024 * clamp(2^floor(log2(n / 1024)), .., 64).
size_t sog_palette_size(size_t n);

// Writes `cloud` to `path` (a .sog file), through a temporary sibling renamed at the end, so a
// failure leaves nothing. Gaussians are stored in Morton order of their means (smaller images);
// extra properties (labels) are not part of SOG and are dropped.
void write_sog(const GaussianCloud& cloud, const std::filesystem::path& path, const SogQuantizer& quantizer);

}  // namespace pg::data

#pragma once
// CPU reference of engine/compress/kmeans's assignment: nearest centroid by squared distance,
// ties to the lower index, in double.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace pg::ref {

std::vector<uint32_t> nearest_centroids(const std::vector<float>& points, const std::vector<float>& centroids,
                                        size_t dims);
// Sum of squared distances of the points to their labels' centroids.
double clustering_error(const std::vector<float>& points, const std::vector<float>& centroids,
                        const std::vector<uint32_t>& labels, size_t dims);

}  // namespace pg::ref

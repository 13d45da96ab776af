#include "tests/reference/kmeans_reference.h"

#include <limits>

namespace pg::ref {

std::vector<uint32_t> nearest_centroids(const std::vector<float>& points, const std::vector<float>& centroids,
                                        size_t dims) {
    const size_t n = points.size() / dims, k = centroids.size() / dims;
    std::vector<uint32_t> labels(n, 0);
    for (size_t i = 0; i < n; ++i) {
        double best = std::numeric_limits<double>::infinity();
        for (size_t c = 0; c < k; ++c) {
            double d2 = 0;
            for (size_t d = 0; d < dims; ++d) {
                const double e = double(points[i * dims + d]) - centroids[c * dims + d];
                d2 += e * e;
            }
            if (d2 < best) best = d2, labels[i] = uint32_t(c);
        }
    }
    return labels;
}

double clustering_error(const std::vector<float>& points, const std::vector<float>& centroids,
                        const std::vector<uint32_t>& labels, size_t dims) {
    double sum = 0;
    for (size_t i = 0; i < labels.size(); ++i)
        for (size_t d = 0; d < dims; ++d) {
            const double e = double(points[i * dims + d]) - centroids[labels[i] * dims + d];
            sum += e * e;
        }
    return sum;
}

}  // namespace pg::ref

#include "tests/reference/kmeans_reference.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

namespace pg::ref {

std::vector<float> kmeans_start(const std::vector<float>& points, size_t dims, size_t k, uint64_t seed) {
    const size_t n = points.size() / dims;
    std::mt19937_64 rng(seed);
    std::vector<size_t> index(n);
    std::iota(index.begin(), index.end(), size_t(0));
    std::vector<float> centroids;
    for (size_t c = 0; c < k; ++c) {
        std::swap(index[c], index[c + rng() % (n - c)]);
        centroids.insert(centroids.end(), points.begin() + long(index[c] * dims),
                         points.begin() + long((index[c] + 1) * dims));
    }
    return centroids;
}

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

void move_centroids(const std::vector<float>& points, size_t dims, const std::vector<uint32_t>& labels,
                    std::vector<float>& centroids) {
    std::vector<double> sum(centroids.size(), 0.0);
    std::vector<size_t> count(centroids.size() / dims, 0);
    for (size_t i = 0; i < labels.size(); ++i) {
        ++count[labels[i]];
        for (size_t d = 0; d < dims; ++d) sum[labels[i] * dims + d] += points[i * dims + d];
    }
    for (size_t c = 0; c < count.size(); ++c)
        if (count[c])
            for (size_t d = 0; d < dims; ++d) centroids[c * dims + d] = float(sum[c * dims + d] / double(count[c]));
}

KmeansResult lloyd(const std::vector<float>& points, size_t dims, std::vector<float> centroids, int iterations) {
    for (int step = 0; step < iterations; ++step)
        move_centroids(points, dims, nearest_centroids(points, centroids, dims), centroids);
    std::vector<uint32_t> labels = nearest_centroids(points, centroids, dims);
    return {std::move(centroids), std::move(labels)};
}

KmeansResult kmeans(const std::vector<float>& points, size_t dims, size_t k, int iterations, uint64_t seed) {
    const size_t n = points.size() / dims;
    if (k >= n) {
        KmeansResult own;
        for (size_t c = 0; c < k; ++c)
            for (size_t d = 0; d < dims; ++d) own.centroids.push_back(points[std::min(c, n - 1) * dims + d]);
        own.labels.resize(n);
        std::iota(own.labels.begin(), own.labels.end(), 0u);
        return own;
    }
    return lloyd(points, dims, kmeans_start(points, dims, k, seed), iterations);
}

std::vector<float> codebook_start(const std::vector<float>& values, size_t k) {
    // k equal steps of the cumulative cube-rooted counts of a 4096-bin histogram of the range,
    // interpolated within a bin.
    const double lo = *std::min_element(values.begin(), values.end());
    const double hi = *std::max_element(values.begin(), values.end());
    std::vector<float> start(k, float(lo));
    if (!(hi > lo)) return start;
    const size_t bins = 4096;
    std::vector<double> weight(bins, 0.0);
    for (float v : values) weight[std::min(bins - 1, size_t((v - lo) / (hi - lo) * bins))] += 1.0;
    for (double& w : weight) w = std::cbrt(w);
    const double total = std::accumulate(weight.begin(), weight.end(), 0.0);
    double below = 0;
    size_t b = 0;
    for (size_t i = 0; i < k; ++i) {
        const double target = (double(i) + 0.5) / double(k) * total;
        while (b + 1 < bins && below + weight[b] < target) below += weight[b++];
        const double within = weight[b] > 0 ? (target - below) / weight[b] : 0.5;
        start[i] = float(lo + (double(b) + std::clamp(within, 0.0, 1.0)) / double(bins) * (hi - lo));
    }
    return start;
}

std::vector<float> quantile_start(const std::vector<float>& values, size_t k) {
    std::vector<float> sorted = values;
    std::sort(sorted.begin(), sorted.end());
    std::vector<float> start(k);
    for (size_t i = 0; i < k; ++i)
        start[i] = sorted[std::min(sorted.size() - 1, (2 * i + 1) * sorted.size() / (2 * k))];
    return start;
}

KmeansResult codebook_1d(const std::vector<float>& values, std::vector<float> start, int iterations) {
    KmeansResult r = lloyd(values, 1, std::move(start), iterations);
    const size_t k = r.centroids.size();
    std::vector<uint32_t> order(k), rank(k);
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(),
                     [&](uint32_t a, uint32_t b) { return r.centroids[a] < r.centroids[b]; });
    std::vector<float> ascending(k);
    for (uint32_t i = 0; i < k; ++i) rank[order[i]] = i, ascending[i] = r.centroids[order[i]];
    for (auto& l : r.labels) l = rank[l];
    r.centroids = std::move(ascending);
    return r;
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

#include "engine/compress/kmeans.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <stdexcept>
#include <string>

#include "engine/compress/lloyd.h"

namespace pg::compress {

Clusters kmeans(vk::Context& ctx, const std::vector<float>& points, size_t dims, size_t k, int iterations,
                uint64_t seed) {
    if (dims == 0 || dims > kMaxKmeansDims || points.size() % dims != 0)
        throw std::invalid_argument("k-means: dims must be 1.." + std::to_string(kMaxKmeansDims) +
                                    " and divide the point data (" + std::to_string(points.size()) + " floats)");
    const size_t n = points.size() / dims;
    if (n == 0 || k == 0 || iterations < 0)
        throw std::invalid_argument("k-means: needs points, clusters and iterations >= 0");
    std::vector<float> centroids(k * dims);
    if (k >= n) {  // every point its own cluster
        for (size_t c = 0; c < k; ++c) std::copy_n(&points[std::min(c, n - 1) * dims], dims, &centroids[c * dims]);
        Clusters out{std::move(centroids), std::vector<uint32_t>(n)};
        std::iota(out.labels.begin(), out.labels.end(), 0u);
        return out;
    }
    // k distinct points: the first k of a seeded partial Fisher-Yates shuffle of the indices.
    std::mt19937_64 rng(seed);
    std::vector<uint32_t> pick(n);
    std::iota(pick.begin(), pick.end(), 0u);
    for (size_t c = 0; c < k; ++c) {
        std::swap(pick[c], pick[c + size_t(rng() % (n - c))]);
        std::copy_n(&points[size_t(pick[c]) * dims], dims, &centroids[c * dims]);
    }
    return lloyd(ctx, points, dims, std::move(centroids), iterations);
}

Clusters codebook_1d(vk::Context& ctx, const std::vector<float>& values, size_t k, int iterations) {
    if (values.empty() || k == 0 || iterations < 0)
        throw std::invalid_argument("codebook: needs values, entries and iterations >= 0");
    if (!std::all_of(values.begin(), values.end(), [](float v) { return std::isfinite(v); }))
        throw std::invalid_argument("codebook: the values must be finite");
    // Levels at density ∝ p(x)^(1/3) (kmeans.h says why), read off a histogram: k equal steps of
    // the cumulative cube-rooted bin counts, interpolated within a bin.
    const auto [lo_it, hi_it] = std::minmax_element(values.begin(), values.end());
    const double lo = *lo_it, hi = *hi_it;
    std::vector<float> start(k, float(lo));
    if (hi > lo) {
        constexpr size_t kBins = 4096;
        std::vector<double> weight(kBins, 0.0);
        for (float v : values) weight[std::min(kBins - 1, size_t((v - lo) / (hi - lo) * kBins))] += 1.0;
        double total = 0;
        for (double& w : weight) total += (w = std::cbrt(w));
        double below = 0;
        size_t b = 0;
        for (size_t i = 0; i < k; ++i) {
            const double target = (double(i) + 0.5) / double(k) * total;
            while (b + 1 < kBins && below + weight[b] < target) below += weight[b++];
            const double within = weight[b] > 0 ? (target - below) / weight[b] : 0.5;
            start[i] = float(lo + (double(b) + std::clamp(within, 0.0, 1.0)) / kBins * (hi - lo));
        }
    }
    Clusters c = lloyd(ctx, values, 1, std::move(start), iterations);
    // Ascending codebook: Lloyd's keeps 1-D centroids in order, but equal starts may swap.
    std::vector<uint32_t> order(k), rank(k);
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(),
                     [&](uint32_t a, uint32_t b) { return c.centroids[a] < c.centroids[b]; });
    std::vector<float> ascending(k);
    for (uint32_t r = 0; r < k; ++r) rank[order[r]] = r, ascending[r] = c.centroids[order[r]];
    for (auto& l : c.labels) l = rank[l];
    c.centroids = std::move(ascending);
    return c;
}

}  // namespace pg::compress

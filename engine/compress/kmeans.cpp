#include "engine/compress/kmeans.h"

#include <algorithm>
#include <memory>
#include <numeric>
#include <random>
#include <stdexcept>
#include <string>

#include "engine/sort/radix_sort.h"
#include "engine/vk/buffer.h"
#include "engine/vk/commands.h"

namespace pg::compress {

namespace {

struct AssignPush {
    uint32_t n, k, dims;
};
struct CountPush {
    uint32_t n;
};
struct UpdatePush {
    uint32_t k, dims;
};

uint32_t bits_for(size_t k) {
    uint32_t b = 1;
    while ((size_t(1) << b) < k) ++b;
    return b;
}

// Runs the Lloyd steps from `centroids`; the points stay on the device throughout.
Clusters lloyd(vk::Context& ctx, const std::vector<float>& points, size_t dims, std::vector<float> centroids,
               int iterations) {
    const size_t n = points.size() / dims, k = centroids.size() / dims;
    const VkDeviceSize range = ctx.info().max_storage_buffer_range;
    const VkDeviceSize point_bytes = VkDeviceSize(dims) * sizeof(float);
    if (VkDeviceSize(k) * point_bytes > range)
        throw std::runtime_error("k-means: " + std::to_string(k) + " centroids of " + std::to_string(dims) +
                                 " floats pass the device's largest binding (" + std::to_string(range) + " bytes)");
    // Windows of points whose floats and labels each fit one binding, at a 256-byte aligned offset.
    const size_t window = std::max<size_t>(64, size_t(range / point_bytes) / 64 * 64);
    // The update runs on the device when the points fit one binding (the members of a cluster are
    // anywhere among them); past that, on the host.
    const bool device_means = VkDeviceSize(n) * point_bytes <= range;
    vk::Buffer pts = vk::upload_vector(ctx, points, "kmeans points");
    vk::Buffer cen(ctx, std::max<VkDeviceSize>(16, k * point_bytes), vk::MemoryUse::Device, "kmeans centroids");
    const VkDeviceSize label_bytes = std::max<VkDeviceSize>(16, n * sizeof(uint32_t));
    vk::Buffer lab(ctx, label_bytes, vk::MemoryUse::Device, "kmeans labels");
    vk::Buffer keys, members, order, start, end;
    std::unique_ptr<sort::RadixSort> sorter;
    if (device_means && iterations > 0) {
        std::vector<uint32_t> iota(n);
        std::iota(iota.begin(), iota.end(), 0u);
        order = vk::upload_vector(ctx, iota, "kmeans order");
        keys = vk::Buffer(ctx, label_bytes, vk::MemoryUse::Device, "kmeans keys");
        members = vk::Buffer(ctx, label_bytes, vk::MemoryUse::Device, "kmeans members");
        start = vk::Buffer(ctx, std::max<VkDeviceSize>(16, k * sizeof(uint32_t)), vk::MemoryUse::Device, "kmeans start");
        end = vk::Buffer(ctx, std::max<VkDeviceSize>(16, k * sizeof(uint32_t)), vk::MemoryUse::Device, "kmeans end");
        sorter = std::make_unique<sort::RadixSort>(ctx);
    }
    vk::CommandList cmd(ctx);
    Clusters out;
    vk::upload(ctx, cen, centroids.data(), centroids.size() * sizeof(float));
    for (int step = 0;; ++step) {
        for (size_t first = 0; first < n; first += window) {
            const size_t count = std::min(window, n - first);
            const AssignPush push{uint32_t(count), uint32_t(k), uint32_t(dims)};
            cmd.dispatch("compress/kmeans_assign",
                         {vk::BufferRange(pts, first * point_bytes, count * point_bytes), cen,
                          vk::BufferRange(lab, first * sizeof(uint32_t), count * sizeof(uint32_t))},
                         push, vk::ceil_div(count, 64));
        }
        if (step == iterations) break;
        if (device_means) {
            // Members of each cluster in point order (a stable sort by label), their runs, the means.
            cmd.copy(lab, keys, n * sizeof(uint32_t));
            cmd.copy(order, members, n * sizeof(uint32_t));
            sorter->sort(cmd, keys, members, uint32_t(n), bits_for(k), sort::KeyWidth::Bits32);
            cmd.fill(start, 0);
            cmd.fill(end, 0);
            cmd.dispatch("compress/kmeans_bounds", {keys, start, end}, CountPush{uint32_t(n)}, vk::ceil_div(n, 256));
            cmd.dispatch("compress/kmeans_update", {pts, members, start, end, cen}, UpdatePush{uint32_t(k), uint32_t(dims)},
                         vk::ceil_div(k * dims, 64));
        } else {
            cmd.submit_and_wait();
            move_centroids(points, dims, vk::download_vector<uint32_t>(ctx, lab, n), centroids);
            vk::upload(ctx, cen, centroids.data(), centroids.size() * sizeof(float));
        }
    }
    cmd.submit_and_wait();
    out.labels = vk::download_vector<uint32_t>(ctx, lab, n);
    out.centroids = vk::download_vector<float>(ctx, cen, k * dims);
    return out;
}

void check_dims(size_t points, size_t dims) {
    if (dims == 0 || dims > kMaxKmeansDims || points % dims != 0)
        throw std::invalid_argument("k-means: dims must be 1.." + std::to_string(kMaxKmeansDims) +
                                    " and divide the point data");
}

}  // namespace

void move_centroids(const std::vector<float>& points, size_t dims, const std::vector<uint32_t>& labels,
                    std::vector<float>& centroids) {
    const size_t k = centroids.size() / dims;
    std::vector<double> sum(centroids.size(), 0.0);
    std::vector<uint64_t> count(k, 0);
    for (size_t i = 0; i < labels.size(); ++i) {
        ++count[labels[i]];
        for (size_t d = 0; d < dims; ++d) sum[labels[i] * dims + d] += points[i * dims + d];
    }
    for (size_t c = 0; c < k; ++c)
        if (count[c])
            for (size_t d = 0; d < dims; ++d) centroids[c * dims + d] = float(sum[c * dims + d] / double(count[c]));
}

Clusters kmeans(vk::Context& ctx, const std::vector<float>& points, size_t dims, size_t k, int iterations,
                uint64_t seed) {
    check_dims(points.size(), dims);
    const size_t n = points.size() / dims;
    if (n == 0 || k == 0) throw std::invalid_argument("k-means: no points or no clusters");
    std::vector<float> centroids(k * dims);
    if (k >= n) {  // every point its own cluster
        Clusters out;
        for (size_t c = 0; c < k; ++c) std::copy_n(&points[std::min(c, n - 1) * dims], dims, &centroids[c * dims]);
        out.centroids = std::move(centroids);
        out.labels.resize(n);
        std::iota(out.labels.begin(), out.labels.end(), 0u);
        return out;
    }
    // k distinct points: the first k of a seeded partial Fisher-Yates shuffle of the indices.
    std::mt19937_64 rng(seed);
    std::vector<uint32_t> pick(n);
    std::iota(pick.begin(), pick.end(), 0u);
    for (size_t c = 0; c < k; ++c) {
        const size_t j = c + size_t(rng() % (n - c));
        std::swap(pick[c], pick[j]);
        std::copy_n(&points[size_t(pick[c]) * dims], dims, &centroids[c * dims]);
    }
    return lloyd(ctx, points, dims, std::move(centroids), iterations);
}

Clusters codebook_1d(vk::Context& ctx, const std::vector<float>& values, size_t k, int iterations) {
    if (values.empty() || k == 0) throw std::invalid_argument("codebook: no values or no entries");
    // Start where a mean-squared-error quantiser puts its levels: at density ∝ p(x)^(1/3)
    // (Panter and Dite), read off a histogram; plain quantiles starve the tails, where log-scales
    // and colours that matter to the picture live.
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
    // Ascending codebook (Lloyd's keeps 1-D centroids ordered, but equal starts may swap).
    std::vector<uint32_t> order(k), rank(k);
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return c.centroids[a] < c.centroids[b]; });
    std::vector<float> ascending(k);
    for (uint32_t r = 0; r < k; ++r) rank[order[r]] = r, ascending[r] = c.centroids[order[r]];
    for (auto& l : c.labels) l = rank[l];
    c.centroids = std::move(ascending);
    return c;
}

}  // namespace pg::compress

#include "engine/compress/lloyd.h"

#include <algorithm>
#include <cstdint>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <string>

#include "engine/sort/radix_sort.h"
#include "engine/vk/buffer.h"
#include "engine/vk/commands.h"
#include "shaders/compress/kmeans_shared.h"

namespace pg::compress {

namespace {

using gpu::KmeansAssignPush, gpu::KmeansBoundsPush, gpu::KmeansPiecePush, gpu::KmeansClusterPush;

struct AssignKernel {
    size_t dims, block, rows;  // floats per point, centroids per dispatch, points per invocation
    const char* shader;
};
#define PG_KMEANS_KERNEL(d) {d, PG_KMEANS_BLOCK_D##d, PG_KMEANS_ROWS_D##d, "compress/kmeans_assign_d" #d}
constexpr AssignKernel kAssignKernels[] = {PG_KMEANS_KERNEL(1), PG_KMEANS_KERNEL(3), PG_KMEANS_KERNEL(9),
                                           PG_KMEANS_KERNEL(24), PG_KMEANS_KERNEL(45)};
#undef PG_KMEANS_KERNEL
static_assert(PG_KMEANS_MAX_DIMS == 45 && kMaxKmeansDims == PG_KMEANS_MAX_DIMS);

constexpr uint32_t kInfinity = 0x7F800000u;  // +inf as float bits
// Points per window at most: 2^25 / PG_KMEANS_CHUNK chunks keep kmeans_accumulate's loop
// under lavapipe's 65535 iterations.
constexpr size_t kMaxWindow = size_t(1) << 25;

// Rows of `from` floats widened to `to` with zeros (a zero coordinate changes no distance) or
// narrowed back.
std::vector<float> rewidth(const std::vector<float>& v, size_t from, size_t to) {
    const size_t rows = v.size() / from;
    std::vector<float> out(rows * to, 0.0f);
    for (size_t r = 0; r < rows; ++r) std::copy_n(&v[r * from], std::min(from, to), &out[r * to]);
    return out;
}

uint32_t label_bits(size_t k) {
    uint32_t b = 0;
    while ((size_t(1) << b) < k) ++b;
    return b;
}

vk::Buffer device_buffer(vk::Context& ctx, VkDeviceSize bytes, const char* name) {
    return vk::Buffer(ctx, std::max<VkDeviceSize>(16, bytes), vk::MemoryUse::Device, name);
}

}  // namespace

Clusters lloyd(vk::Context& ctx, const std::vector<float>& input, size_t input_dims, std::vector<float> centroids,
               int iterations, size_t max_window) {
    if (max_window % 64 != 0) throw std::invalid_argument("k-means: max_window must be a multiple of 64");
    const AssignKernel* kernel = std::find_if(std::begin(kAssignKernels), std::end(kAssignKernels),
                                              [&](const AssignKernel& a) { return a.dims >= input_dims; });
    if (input_dims == 0 || kernel == std::end(kAssignKernels))
        throw std::invalid_argument("k-means: dims must be 1.." + std::to_string(kMaxKmeansDims));
    const size_t dims = kernel->dims;
    std::vector<float> widened;
    if (dims != input_dims) {
        widened = rewidth(input, input_dims, dims);
        centroids = rewidth(centroids, input_dims, dims);
    }
    const std::vector<float>& points = dims != input_dims ? widened : input;
    const size_t n = points.size() / dims, k = centroids.size() / dims;
    const VkDeviceSize range = ctx.info().max_storage_buffer_range, row = dims * sizeof(float);
    if (k * row > range)
        throw std::runtime_error("k-means: " + std::to_string(k) + " centroids of " + std::to_string(dims) +
                                 " floats pass the device's largest storage binding (" + std::to_string(range) +
                                 " bytes)");
    if (n > UINT32_MAX || k > UINT32_MAX)
        throw std::invalid_argument("k-means: more than 2^32 points or centroids");

    // Windows of points, whole multiples of 64 (256-byte aligned slices of the per-point buffers).
    size_t window = std::min<size_t>(range / row, kMaxWindow) / 64 * 64;
    if (max_window) window = std::min(window, max_window);
    window = std::min(window, n);
    std::vector<vk::Buffer> windows;
    for (size_t first = 0; first < n; first += window) {
        const size_t count = std::min(window, n - first);
        windows.emplace_back(ctx, count * row, vk::MemoryUse::Device, "kmeans points");
        vk::upload(ctx, windows.back(), &points[first * dims], count * row);
    }
    vk::Buffer cen = device_buffer(ctx, k * row, "kmeans centroids");
    vk::upload(ctx, cen, centroids.data(), k * row);
    vk::Buffer best = device_buffer(ctx, n * sizeof(float), "kmeans best");
    vk::Buffer labels = device_buffer(ctx, n * sizeof(uint32_t), "kmeans labels");

    // The update's buffers: a window's sorted labels and members, cluster runs, sums.
    const size_t chunks = (window + PG_KMEANS_CHUNK - 1) / PG_KMEANS_CHUNK;
    vk::Buffer keys, members, order, start, end, whole, head, tail, sum, carry, count;
    std::unique_ptr<sort::RadixSort> sorter;
    if (iterations > 0) {
        std::vector<uint32_t> iota(window);
        std::iota(iota.begin(), iota.end(), 0u);
        order = vk::upload_vector(ctx, iota, "kmeans order");
        keys = device_buffer(ctx, window * sizeof(uint32_t), "kmeans keys");
        members = device_buffer(ctx, window * sizeof(uint32_t), "kmeans members");
        start = device_buffer(ctx, k * sizeof(uint32_t), "kmeans start");
        end = device_buffer(ctx, k * sizeof(uint32_t), "kmeans end");
        whole = device_buffer(ctx, k * row, "kmeans whole");
        head = device_buffer(ctx, chunks * row, "kmeans head");
        tail = device_buffer(ctx, chunks * row, "kmeans tail");
        sum = device_buffer(ctx, k * row, "kmeans sum");
        carry = device_buffer(ctx, k * row, "kmeans carry");
        count = device_buffer(ctx, k * sizeof(uint32_t), "kmeans count");
        sorter = std::make_unique<sort::RadixSort>(ctx);
    }
    const KmeansClusterPush per_cluster{uint32_t(k), uint32_t(dims), 0, 0};

    vk::CommandList cmd(ctx);
    for (int step = 0;; ++step) {
        cmd.fill(best, kInfinity);
        cmd.fill(labels, 0);
        for (size_t w = 0, first = 0; first < n; ++w, first += window) {
            const size_t points_here = std::min(window, n - first);
            const vk::BufferRange best_here(best, first * sizeof(float), points_here * sizeof(float));
            const vk::BufferRange labels_here(labels, first * sizeof(uint32_t), points_here * sizeof(uint32_t));
            for (size_t block = 0; block < k; block += kernel->block)
                cmd.dispatch(kernel->shader, {windows[w], cen, best_here, labels_here},
                             KmeansAssignPush{uint32_t(points_here), uint32_t(block), uint32_t(k - 1), 0},
                             vk::ceil_div(points_here, PG_KMEANS_THREADS * kernel->rows));
        }
        if (step == iterations) break;

        cmd.fill(sum, 0);
        cmd.fill(carry, 0);
        cmd.fill(count, 0);
        for (size_t w = 0, first = 0; first < n; ++w, first += window) {
            const size_t points_here = std::min(window, n - first);
            const uint32_t chunks_here = vk::ceil_div(points_here, PG_KMEANS_CHUNK);
            cmd.copy(labels, keys, points_here * sizeof(uint32_t), first * sizeof(uint32_t));
            cmd.copy(order, members, points_here * sizeof(uint32_t));
            sorter->sort(cmd, keys, members, uint32_t(points_here), label_bits(k), sort::KeyWidth::Bits32);
            cmd.fill(start, 0);
            cmd.fill(end, 0);
            cmd.dispatch("compress/kmeans_bounds", {keys, start, end}, KmeansBoundsPush{uint32_t(points_here), 0, 0, 0},
                         vk::ceil_div(points_here, 256));
            cmd.dispatch("compress/kmeans_piece_sums", {keys, members, windows[w], whole, head, tail},
                         KmeansPiecePush{uint32_t(points_here), uint32_t(dims), chunks_here, 0},
                         vk::ceil_div(uint64_t(chunks_here) * dims, PG_KMEANS_THREADS));
            cmd.dispatch("compress/kmeans_accumulate", {start, end, whole, head, tail, sum, carry, count}, per_cluster,
                         vk::ceil_div(k * dims, PG_KMEANS_THREADS));
        }
        cmd.dispatch("compress/kmeans_update", {sum, count, cen}, per_cluster,
                     vk::ceil_div(k * dims, PG_KMEANS_THREADS));
        cmd.submit_and_wait();  // one step per submission: bounded command buffers
    }
    cmd.submit_and_wait();
    Clusters out;
    out.labels = vk::download_vector<uint32_t>(ctx, labels, n);
    out.centroids = vk::download_vector<float>(ctx, cen, k * dims);
    if (dims != input_dims) out.centroids = rewidth(out.centroids, dims, input_dims);
    return out;
}

}  // namespace pg::compress

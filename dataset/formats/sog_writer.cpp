// write_sog: the inverse of sog_decode.cpp's v2 path. Quantisation rounds to the nearest step
// (splat-transform truncates), so a round trip errs by at most half a step.
#include "dataset/formats/sog_writer.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "dataset/error.h"
#include "dataset/formats/webp_image.h"
#include "dataset/formats/zip_archive.h"

namespace pg::data {

namespace {

uint64_t spread_bits_21(uint64_t v) {
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffULL;
    v = (v | v << 16) & 0x1f0000ff0000ffULL;
    v = (v | v << 8) & 0x100f00f00f00f00fULL;
    v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
    v = (v | v << 2) & 0x1249249249249249ULL;
    return v;
}

// Gaussian order along a Morton curve over the means' bounding box: neighbours in the image are
// neighbours in space, which is what makes the lossless WebPs small.
std::vector<uint32_t> morton_order(const GaussianCloud& c) {
    glm::vec3 lo(INFINITY), hi(-INFINITY);
    for (const auto& m : c.mean) lo = glm::min(lo, m), hi = glm::max(hi, m);
    const glm::vec3 extent = glm::max(hi - lo, glm::vec3(1e-20f));
    std::vector<uint64_t> code(c.size());
    for (size_t i = 0; i < c.size(); ++i) {
        const glm::vec3 t = (c.mean[i] - lo) / extent * float((1 << 21) - 1);
        code[i] = spread_bits_21(uint64_t(t.x)) | spread_bits_21(uint64_t(t.y)) << 1 | spread_bits_21(uint64_t(t.z)) << 2;
    }
    std::vector<uint32_t> order(c.size());
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return code[a] < code[b]; });
    return order;
}

double log_transform(double v) { return (v < 0 ? -1.0 : 1.0) * std::log(std::abs(v) + 1.0); }

uint8_t to_byte(double unit) { return uint8_t(std::clamp(std::lround(unit * 255.0), 0L, 255L)); }

struct Images {
    int width, height;
    RgbaImage make() const {
        RgbaImage img;
        img.width = width, img.height = height;
        img.rgba.assign(img.pixels() * 4, 0);
        for (size_t p = 0; p < img.pixels(); ++p) img.rgba[p * 4 + 3] = 255;
        return img;
    }
};

std::vector<double> as_doubles(const std::vector<float>& v) { return {v.begin(), v.end()}; }

void check_clusters(const SogClusters& c, size_t k, size_t dims, size_t n, const char* what) {
    if (c.centroids.size() != k * dims || c.labels.size() != n)
        throw std::logic_error(std::string("SOG writer: the ") + what + " quantizer returned the wrong sizes");
    for (uint32_t l : c.labels)
        if (l >= k) throw std::logic_error(std::string("SOG writer: the ") + what + " quantizer returned a label past k");
}

}  // namespace

size_t sog_palette_size(size_t n) {
    const double ratio = std::floor(std::log2(std::max<double>(double(n), 1.0) / 1024.0));
    return size_t(std::min(64.0, std::pow(2.0, ratio)) * 1024.0);
}

void write_sog(const GaussianCloud& cloud, const std::filesystem::path& path, const SogQuantizer& q) {
    const size_t n = cloud.size();
    if (n == 0) throw InputError(path.string(), "cannot write a SOG of no Gaussians");
    const std::vector<uint32_t> order = morton_order(cloud);
    const int width = int(std::ceil(std::sqrt(double(n)) / 4.0) * 4.0);
    const int height = int(std::ceil(double(n) / width / 4.0) * 4.0);
    const Images layout{width, height};
    const size_t stride = size_t(cloud.coeffs()) * 3;
    std::vector<ZipEntry> entries;
    auto add = [&](const std::string& name, const RgbaImage& img) { entries.push_back({name, encode_webp_lossless(img)}); };
    nlohmann::json meta;
    meta["version"] = 2;
    meta["asset"] = {{"generator", "pointgauss"}};
    meta["count"] = n;

    {  // means: 16 bits of sign(x)·ln(|x|+1) between the per-axis min and max
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (const auto& m : cloud.mean)
            for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], log_transform(m[a])), hi[a] = std::max(hi[a], log_transform(m[a]));
        RgbaImage l = layout.make(), u = layout.make();
        for (size_t t = 0; t < n; ++t)
            for (int a = 0; a < 3; ++a) {
                const double range = hi[a] - lo[a];
                const double unit = range > 0 ? (log_transform(cloud.mean[order[t]][a]) - lo[a]) / range : 0.0;
                const long v = std::clamp(std::lround(unit * 65535.0), 0L, 65535L);
                l.rgba[t * 4 + a] = uint8_t(v & 0xff), u.rgba[t * 4 + a] = uint8_t(v >> 8);
            }
        add("means_l.webp", l), add("means_u.webp", u);
        meta["means"] = {{"mins", std::vector<double>(lo, lo + 3)},
                         {"maxs", std::vector<double>(hi, hi + 3)},
                         {"files", {"means_l.webp", "means_u.webp"}}};
    }
    {  // quats: the smallest three of the unit quaternion, largest made positive, index in alpha
        RgbaImage img = layout.make();
        for (size_t t = 0; t < n; ++t) {
            const glm::vec4& r = cloud.rotation[order[t]];
            double v[4] = {r[0], r[1], r[2], r[3]};
            const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + v[3] * v[3]);
            int largest = 0;
            for (int k = 0; k < 4; ++k) {
                v[k] /= len;
                if (std::abs(v[k]) > std::abs(v[largest])) largest = k;
            }
            const double sign = v[largest] < 0 ? -1.0 : 1.0;
            for (int k = 0, j = 0; k < 4; ++k)
                if (k != largest) img.rgba[t * 4 + j++] = to_byte(sign * v[k] * std::sqrt(2.0) * 0.5 + 0.5);
            img.rgba[t * 4 + 3] = uint8_t(252 + largest);
        }
        add("quats.webp", img);
    }
    auto codebook_image = [&](const std::string& name, auto value_of, bool opacity_alpha) {
        std::vector<float> pooled(n * 3);
        for (int c = 0; c < 3; ++c)
            for (size_t t = 0; t < n; ++t) pooled[size_t(c) * n + t] = value_of(order[t], c);
        const SogClusters book = q.codebook(pooled);
        check_clusters(book, 256, 1, pooled.size(), "codebook");
        RgbaImage img = layout.make();
        for (int c = 0; c < 3; ++c)
            for (size_t t = 0; t < n; ++t) img.rgba[t * 4 + size_t(c)] = uint8_t(book.labels[size_t(c) * n + t]);
        if (opacity_alpha)
            for (size_t t = 0; t < n; ++t) img.rgba[t * 4 + 3] = to_byte(opacity_from_logit(cloud.opacity_logit[order[t]]));
        add(name, img);
        return as_doubles(book.centroids);
    };
    meta["scales"] = {{"codebook", codebook_image("scales.webp", [&](uint32_t i, int c) { return cloud.log_scale[i][c]; }, false)},
                      {"files", {"scales.webp"}}};
    meta["quats"] = {{"files", {"quats.webp"}}};
    meta["sh0"] = {{"codebook", codebook_image("sh0.webp", [&](uint32_t i, int c) { return cloud.sh[i * stride + size_t(c)]; }, true)},
                   {"files", {"sh0.webp"}}};

    if (cloud.sh_degree > 0) {  // SH palette: k-means of each Gaussian's rest coefficients, then a codebook
        const size_t coeffs = size_t(cloud.coeffs()) - 1, dims = coeffs * 3;
        const size_t k = sog_palette_size(n);
        // Rows in f_rest order: channel-major, as the palette stores them.
        std::vector<float> points(n * dims);
        for (size_t i = 0; i < n; ++i)
            for (int c = 0; c < 3; ++c)
                for (size_t j = 0; j < coeffs; ++j)
                    points[i * dims + size_t(c) * coeffs + j] = cloud.sh[i * stride + (1 + j) * 3 + size_t(c)];
        const SogClusters palette = q.kmeans(points, dims, k);
        check_clusters(palette, k, dims, n, "k-means");
        const SogClusters book = q.codebook(palette.centroids);
        check_clusters(book, 256, 1, palette.centroids.size(), "codebook");
        const int rows = int((k + 63) / 64);
        RgbaImage centroids;
        centroids.width = int(64 * coeffs), centroids.height = rows;
        centroids.rgba.assign(centroids.pixels() * 4, 0);
        for (size_t p = 0; p < centroids.pixels(); ++p) centroids.rgba[p * 4 + 3] = 255;
        for (size_t e = 0; e < k; ++e)
            for (size_t j = 0; j < coeffs; ++j) {
                uint8_t* px = &centroids.rgba[((e / 64) * size_t(centroids.width) + (e % 64) * coeffs + j) * 4];
                for (int c = 0; c < 3; ++c) px[c] = uint8_t(book.labels[e * dims + size_t(c) * coeffs + j]);
            }
        RgbaImage labels = layout.make();
        for (size_t t = 0; t < n; ++t) {
            const uint32_t l = palette.labels[order[t]];
            labels.rgba[t * 4] = uint8_t(l & 0xff), labels.rgba[t * 4 + 1] = uint8_t(l >> 8);
        }
        add("shN_centroids.webp", centroids), add("shN_labels.webp", labels);
        meta["shN"] = {{"count", k},
                       {"bands", cloud.sh_degree},
                       {"codebook", as_doubles(book.centroids)},
                       {"files", {"shN_centroids.webp", "shN_labels.webp"}}};
    }
    const std::string text = meta.dump();
    entries.push_back({"meta.json", std::vector<uint8_t>(text.begin(), text.end())});
    write_zip(path, entries);
}

}  // namespace pg::data

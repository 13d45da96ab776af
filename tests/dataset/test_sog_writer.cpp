// write_sog: what it writes reads back (here and in splat-transform) close to the input, and the
// same input gives the same bytes. The clustering here is a plain CPU Lloyd's k-means; the
// engine's GPU one is checked against its own reference in tests/render/test_kmeans.cpp.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "dataset/atomic_file.h"
#include "dataset/error.h"
#include "dataset/formats/scene_io.h"
#include "dataset/formats/sog.h"
#include "dataset/formats/sog_writer.h"
#include "dataset/formats/zip_archive.h"
#include "tests/test_paths.h"

namespace fs = std::filesystem;
using pg::data::GaussianCloud;

namespace {

pg::data::SogClusters lloyd(const std::vector<float>& points, size_t dims, std::vector<float> centroids, int iterations) {
    const size_t n = points.size() / dims, k = centroids.size() / dims;
    pg::data::SogClusters out;
    out.labels.assign(n, 0);
    for (int it = 0; it <= iterations; ++it) {
        for (size_t i = 0; i < n; ++i) {
            double best = INFINITY;
            for (size_t c = 0; c < k; ++c) {
                double d = 0;
                for (size_t j = 0; j < dims; ++j) d += std::pow(double(points[i * dims + j]) - centroids[c * dims + j], 2);
                if (d < best) best = d, out.labels[i] = uint32_t(c);
            }
        }
        if (it == iterations) break;
        std::vector<double> sum(k * dims, 0.0);
        std::vector<size_t> count(k, 0);
        for (size_t i = 0; i < n; ++i) {
            ++count[out.labels[i]];
            for (size_t j = 0; j < dims; ++j) sum[out.labels[i] * dims + j] += points[i * dims + j];
        }
        for (size_t c = 0; c < k; ++c)
            if (count[c])
                for (size_t j = 0; j < dims; ++j) centroids[c * dims + j] = float(sum[c * dims + j] / double(count[c]));
    }
    out.centroids = std::move(centroids);
    return out;
}

pg::data::SogQuantizer cpu_quantizer() {
    pg::data::SogQuantizer q;
    q.codebook = [](const std::vector<float>& values) {
        std::vector<float> sorted = values;
        std::sort(sorted.begin(), sorted.end());
        std::vector<float> init(256);
        for (size_t i = 0; i < 256; ++i) init[i] = sorted[std::min(sorted.size() - 1, (2 * i + 1) * sorted.size() / 512)];
        auto c = lloyd(values, 1, init, 10);
        // Ascending codebook, labels remapped.
        std::vector<uint32_t> rank(256);
        std::vector<uint32_t> idx(256);
        for (uint32_t i = 0; i < 256; ++i) idx[i] = i;
        std::stable_sort(idx.begin(), idx.end(), [&](uint32_t a, uint32_t b) { return c.centroids[a] < c.centroids[b]; });
        std::vector<float> sorted_c(256);
        for (uint32_t r = 0; r < 256; ++r) rank[idx[r]] = r, sorted_c[r] = c.centroids[idx[r]];
        for (auto& l : c.labels) l = rank[l];
        c.centroids = sorted_c;
        return c;
    };
    q.kmeans = [](const std::vector<float>& points, size_t dims, size_t k) {
        const size_t n = points.size() / dims;
        std::vector<float> init(k * dims);
        for (size_t c = 0; c < k; ++c)
            std::copy_n(&points[(c * n / k) * dims], dims, &init[c * dims]);  // evenly spaced points
        return lloyd(points, dims, init, 5);
    };
    return q;
}

float sigmoid(float x) { return 1.0f / (1.0f + std::exp(-x)); }

}  // namespace

TEST_CASE("sog writer: a written SOG reads back close to its input, the same bytes each time") {
    const GaussianCloud in = pg::data::read_ply(pg::test::fixtures() / "sog" / "bundled_sh3.decoded.ply");
    const auto dir = pg::test::process_scratch("sog-writer");
    const fs::path a = dir / "a.sog", b = dir / "b.sog";
    pg::data::write_sog(in, a, cpu_quantizer());
    pg::data::write_sog(in, b, cpu_quantizer());
    CHECK(pg::data::read_file(a) == pg::data::read_file(b));

    const pg::data::ZipReader zip(a);
    CHECK(zip.names() == std::vector<std::string>{"means_l.webp", "means_u.webp", "quats.webp", "scales.webp", "sh0.webp",
                                                  "shN_centroids.webp", "shN_labels.webp", "meta.json"});
    const auto summary = pg::data::describe_sog(a);
    CHECK(summary.version == 2);
    CHECK(summary.count == in.size());
    CHECK(summary.sh_degree == 3);

    const GaussianCloud out = pg::data::load_scene(a);
    REQUIRE(out.size() == in.size());
    REQUIRE(out.sh_degree == 3);
    // Gaussians come back in Morton order: match each to its input by position.
    double worst_mean = 0, worst_rot = 0, worst_opacity = 0, mean_scale = 0, mean_dc = 0;
    std::vector<bool> used(in.size(), false);
    for (size_t i = 0; i < out.size(); ++i) {
        size_t best = 0;
        float best_d = INFINITY;
        for (size_t j = 0; j < in.size(); ++j) {
            const float d = glm::distance(out.mean[i], in.mean[j]);
            if (d < best_d) best_d = d, best = j;
        }
        used[best] = true;
        worst_mean = std::max(worst_mean, double(best_d));
        const glm::vec4 qa = glm::normalize(out.rotation[i]), qb = glm::normalize(in.rotation[best]);
        worst_rot = std::max(worst_rot, 1.0 - std::abs(double(glm::dot(qa, qb))));
        worst_opacity = std::max(worst_opacity, double(std::abs(sigmoid(out.opacity_logit[i]) - sigmoid(in.opacity_logit[best]))));
        for (int k = 0; k < 3; ++k) {
            mean_scale += std::abs(out.log_scale[i][k] - in.log_scale[best][k]) / (3.0 * double(in.size()));
            mean_dc += std::abs(out.sh[i * 48 + size_t(k)] - in.sh[best * 48 + size_t(k)]) / (3.0 * double(in.size()));
        }
    }
    CHECK(std::count(used.begin(), used.end(), true) == long(in.size()));  // one to one
    CHECK(worst_mean < 2e-3);            // 16 bits over a 5.6 m scene in log space
    CHECK(worst_rot < 1e-3);             // 8-bit smallest three
    CHECK(worst_opacity <= 0.5 / 255 + 1e-6);
    CHECK(mean_scale < 0.02);            // 256-entry codebooks
    CHECK(mean_dc < 0.01);
}

TEST_CASE("sog writer: a failed write leaves nothing behind") {
    GaussianCloud empty;
    const auto dir = pg::test::process_scratch("sog-writer-fail");
    CHECK_THROWS_AS(pg::data::write_sog(empty, dir / "x.sog", cpu_quantizer()), pg::data::InputError);
    CHECK_THROWS_AS(pg::data::write_sog(pg::data::read_ply(pg::test::fixtures() / "sog" / "unbundled_sh1.decoded.ply"),
                                        dir / "no_such_folder" / "x.sog", cpu_quantizer()),
                    pg::data::InputError);
    CHECK(fs::is_empty(dir));
}

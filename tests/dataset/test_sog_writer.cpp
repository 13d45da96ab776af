// write_sog: what it writes reads back (here and in splat-transform) close to the input, and the
// same input gives the same bytes. The clustering here is the CPU reference of the engine's GPU
// k-means (tests/reference/kmeans_reference.h), which tests/render/test_kmeans.cpp checks it against.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "dataset/atomic_file.h"
#include "dataset/error.h"
#include "dataset/formats/scene_io.h"
#include "dataset/formats/sog.h"
#include "dataset/formats/sog_writer.h"
#include "dataset/formats/zip_archive.h"
#include "tests/reference/kmeans_reference.h"
#include "tests/test_paths.h"

namespace fs = std::filesystem;
using pg::data::GaussianCloud;

namespace {

// The CPU reference of the GPU k-means, as the writer's clustering.
pg::data::SogQuantizer cpu_quantizer() {
    pg::data::SogQuantizer q;
    q.codebook = [](const std::vector<float>& values) {
        auto c = pg::ref::codebook_1d(values, pg::ref::codebook_start(values, 256), 10);
        return pg::data::SogClusters{std::move(c.centroids), std::move(c.labels)};
    };
    q.kmeans = [](const std::vector<float>& points, size_t dims, size_t k) {
        auto c = pg::ref::kmeans(points, dims, k, 5, 1);
        return pg::data::SogClusters{std::move(c.centroids), std::move(c.labels)};
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

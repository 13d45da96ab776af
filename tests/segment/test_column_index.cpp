// The column index hands a click's passes the Gaussians near its ROI column: it must never
// leave one out, and what it hands over must give the same ROI and weights as all of them.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include "dataset/up_axis.h"
#include "engine/segment/column_index.h"
#include "engine/segment/prompt_encoder.h"
#include "tests/gpu_fixture.h"
#include "tests/reference/test_scenes.h"

using namespace pg;

TEST_CASE("column index: every Gaussian in a column is a candidate, ascending, each once, and far ones are not") {
    auto scene = ref::random_scene(21, 20000, 0);
    auto& cloud = scene.cloud;
    // A few exact duplicates and far outliers: cells must hold them too.
    for (int k = 0; k < 50; ++k) cloud.mean[size_t(k) * 7 + 1] = cloud.mean[size_t(k) * 7];
    cloud.mean[3] = glm::vec3(40.0f, -25.0f, 60.0f);
    for (int k = 0; k < 300; ++k) cloud.mean[size_t(k) * 61 + 5] *= 200.0f;  // a capture's far floaters
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-1.5, 1.5), len(0.01, 2.0);
    for (const glm::dvec3 up : {glm::dvec3(0, -1, 0), glm::dvec3(0, 0, 1), glm::normalize(glm::dvec3(0.3, -1, 0.2))}) {
        glm::dvec3 a, b;
        data::horizontal_axes(up, a, b);
        seg::ColumnIndex index(cloud, a, b);
        REQUIRE(index.size() == cloud.size());
        for (int q = 0; q < 40; ++q) {
            const glm::dvec3 centre = q == 0 ? glm::dvec3(cloud.mean[3]) : glm::dvec3(u(rng), u(rng), u(rng));
            const double ha = len(rng), hb = len(rng);
            const auto got = index.candidates(centre, ha, hb);
            INFO("query " << q);
            CHECK(std::is_sorted(got.begin(), got.end()));
            CHECK(std::adjacent_find(got.begin(), got.end()) == got.end());
            size_t inside = 0, missed = 0;
            for (uint32_t i = 0; i < cloud.size(); ++i) {
                const glm::dvec3 rel = glm::dvec3(cloud.mean[i]) - centre;
                if (std::abs(glm::dot(rel, a)) <= ha && std::abs(glm::dot(rel, b)) <= hb) {
                    ++inside;
                    missed += !std::binary_search(got.begin(), got.end(), i);
                }
            }
            CHECK(missed == 0);
            // Whole cells around the column, not the scene.
            if (ha < 0.3 && hb < 0.3 && q > 0) CHECK(got.size() < cloud.size() / 4);
            CHECK(got.size() >= inside);
        }
        // Past the grid's bulk: the border cells, which hold the outliers.
        const auto far = index.candidates(glm::dvec3(cloud.mean[3]) + 0.01 * a, 0.05, 0.05);
        CHECK(std::binary_search(far.begin(), far.end(), 3u));
        CHECK(far.size() < cloud.size() / 4);
    }
}

TEST_CASE("prompt encoder: the column index's candidates give the ROI and weights of a pass over every Gaussian") {
    auto scene = ref::random_scene(4, 5000, 0);
    auto& ctx = test::gpu();
    render::GpuScene gpu(ctx, scene.cloud);
    seg::PromptEncoder encoder(ctx);
    std::vector<seg::Anchor> anchors = {{{0.1, 0.2, 0.0}, true, -1}, {{-0.3, 0.1, 0.2}, false, -1}};
    seg::RoiBox roi;
    roi.centre = anchors[0].position;
    data::horizontal_axes(glm::dvec3(0, -1, 0), roi.length_axis, roi.width_axis);
    roi.length = 0.8;
    roi.width = 0.5;
    const auto all = encoder.encode(gpu, anchors, 0.15, roi);
    seg::ColumnIndex index(scene.cloud, roi.length_axis, roi.width_axis);
    const auto candidates = index.candidates(roi.centre, roi.length / 2, roi.width / 2);
    REQUIRE(candidates.size() < scene.cloud.size());
    const auto some = encoder.encode(gpu, anchors, 0.15, roi, &candidates);
    REQUIRE(all.indices.size() > 100);
    CHECK(some.indices == all.indices);
    REQUIRE(some.weights.size() == all.weights.size());
    for (size_t k = 0; k < all.weights.size(); ++k) CHECK(some.weights[k] == all.weights[k]);
    const std::vector<uint32_t> none;
    CHECK(encoder.encode(gpu, anchors, 0.15, roi, &none).indices.empty());
}

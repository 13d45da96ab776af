// The semantic mode's inputs, shared by training and inference: per-Gaussian features, the
// scene's tile cover and the training samples drawn from it.
#include <algorithm>
#include <cmath>
#include <map>

#include <catch2/catch.hpp>

#include "dataset/random.h"
#include "dataset/semantic/gaussian_features.h"
#include "dataset/semantic/scene_tiles.h"
#include "dataset/train/semantic_drawer.h"
#include "dataset/up_axis.h"

using namespace pg::data;
using train::SemanticScene;
using Catch::Matchers::WithinAbs;

namespace {

GaussianCloud flat_gaussian(glm::vec4 rotation) {
    GaussianCloud c;
    c.resize(1);
    c.log_scale[0] = glm::vec3(std::log(0.5f), std::log(0.02f), std::log(2.0f));  // flattest: y
    c.rotation[0] = rotation;
    c.opacity_logit[0] = logit_from_opacity(0.8f);
    c.sh = {(0.9f - 0.5f) / kShC0, (0.2f - 0.5f) / kShC0, (0.5f - 0.5f) / kShC0};
    return c;
}

// A square field of Gaussians at random heights, n of them, side `side`, class 1 above 2 m.
SemanticScene random_scene(size_t n, double side, uint64_t seed) {
    Rng rng(seed);
    SemanticScene s;
    s.name = "random";
    s.up = {0, 0, 1};
    for (size_t i = 0; i < n; ++i) {
        const glm::vec3 p(float(rng.uniform(0, side)), float(rng.uniform(0, side)), float(rng.uniform(0, 6)));
        s.positions.push_back(p);
        s.classes.push_back(p.z > 2.0f ? 1 : 0);
        s.features.push_back(p.z);  // one channel: the height, so a sample shows which Gaussian it took
    }
    return s;
}

}  // namespace

TEST_CASE("semantic features: colour, opacity, sorted scales in voxels and verticality of the flattest axis") {
    // Identity rotation: the flattest axis is y, horizontal for up = z, vertical for up = y.
    const GaussianCloud c = flat_gaussian({1, 0, 0, 0});
    const auto f = semantic::gaussian_features(c, semantic::all_feature_groups(), {0, 0, 1}, 0.5);
    REQUIRE(f.size() == 8);
    REQUIRE(semantic::feature_channels(semantic::all_feature_groups()) == 8);
    CHECK_THAT(f[0], WithinAbs(0.9, 1e-5));
    CHECK_THAT(f[1], WithinAbs(0.2, 1e-5));
    CHECK_THAT(f[2], WithinAbs(0.5, 1e-5));
    CHECK_THAT(f[3], WithinAbs(0.8, 1e-5));
    CHECK_THAT(f[4], WithinAbs(std::log(2.0 / 0.5), 1e-5));  // largest first, in voxels of 0.5
    CHECK_THAT(f[5], WithinAbs(std::log(0.5 / 0.5), 1e-5));
    CHECK_THAT(f[6], WithinAbs(std::log(0.02 / 0.5), 1e-5));
    CHECK_THAT(f[7], WithinAbs(0.0, 1e-5));  // a wall
    CHECK_THAT(semantic::gaussian_features(c, {"verticality"}, {0, -3, 0}, 1.0)[0], WithinAbs(1.0, 1e-5));
    // 90 degrees about x (unnormalised quaternion): y turns into z, the surfel lies flat for up = z.
    const float h = std::sqrt(0.5f) * 3.0f;
    CHECK_THAT(semantic::gaussian_features(flat_gaussian({h, h, 0, 0}), {"verticality"}, {0, 0, 1}, 1.0)[0],
               WithinAbs(1.0, 1e-5));
    CHECK_THROWS_AS(semantic::feature_channels({"rgb", "normals"}), std::invalid_argument);
}

TEST_CASE("scale against spacing: a batch's Gaussians against how densely it samples the surface, raised by a shift") {
    // A plane of Gaussians 0.1 apart, each 0.2 x 0.2 x 0.01: scale against spacing log(0.2 / 0.1),
    // whatever the unit. Every second row and column (a quarter of them, as a batch of an ROI
    // split in four): spacing 0.2, so log(1); the same Gaussians in a scene four times as dense
    // would have been half as large.
    auto plane = [](int step) {
        GaussianCloud c;
        for (int i = 0; i < 40; i += step)
            for (int j = 0; j < 40; j += step) {
                const size_t k = c.size();
                c.resize(k + 1);
                c.mean[k] = glm::vec3(0.1f * float(i), 0.1f * float(j), 0.0f);
                c.log_scale[k] = glm::vec3(std::log(0.2f), std::log(0.2f), std::log(0.01f));
                c.rotation[k] = glm::vec4(1, 0, 0, 0);
            }
        return c;
    };
    const auto groups = semantic::all_feature_groups();
    for (double unit : {0.02, 0.5}) {
        for (int step : {1, 2}) {
            const GaussianCloud c = plane(step);
            auto rows = semantic::gaussian_features(c, groups, {0, 0, 1}, unit);
            const float k = semantic::scale_spacing(rows, groups, c.mean, unit);
            CHECK_THAT(k, WithinAbs(std::log(0.2 / (0.1 * step)), 1e-4));
            // Raised by the difference, the sparse batch reads as the dense one.
            semantic::shift_log_scales(rows, groups, 0.5f);
            CHECK_THAT(rows[4], WithinAbs(std::log(0.2 / unit) + 0.5, 1e-4));
            CHECK_THAT(rows[6], WithinAbs(std::log(0.01 / unit) + 0.5, 1e-4));
            CHECK_THAT(rows[3], WithinAbs(0.5, 1e-6));  // opacity untouched (logit 0)
            CHECK_THAT(semantic::scale_spacing(rows, groups, c.mean, unit), WithinAbs(std::log(0.2 / (0.1 * step)) + 0.5, 1e-4));
        }
    }
    const GaussianCloud one = plane(40);
    CHECK(std::isnan(semantic::scale_spacing(semantic::gaussian_features(one, groups, {0, 0, 1}, 1.0), groups, one.mean, 1.0)));
    CHECK(std::isnan(semantic::scale_spacing(semantic::gaussian_features(one, {"rgb"}, {0, 0, 1}, 1.0), {"rgb"}, one.mean, 1.0)));
}

TEST_CASE("scene tiles: every Gaussian lies in four overlapping tiles, each the column a brute-force search finds") {
    const SemanticScene s = random_scene(3000, 100.0, 7);
    const double tile = 20.0;
    const glm::dvec3 up = glm::normalize(glm::dvec3(0.1, -0.2, 1.0));  // tiles follow up's plane, not the axes
    const semantic::SceneTiling tiling(s.positions, up, tile);
    std::vector<int> count(s.size(), 0);
    for (size_t k = 0; k < tiling.size(); ++k) {
        const auto members = tiling.members(k);
        REQUIRE(!members.empty());
        REQUIRE(std::is_sorted(members.begin(), members.end()));
        for (uint32_t g : members) ++count[g];
        // The brute-force column (closed bounds) holds the tile's members and at most the ones on its edges.
        const auto brute = semantic::column_members(s.positions, up, tiling.centre(k), tile);
        REQUIRE(std::includes(brute.begin(), brute.end(), members.begin(), members.end()));
        REQUIRE(brute.size() - members.size() <= 2);
        // The frame puts the tile's ground (its 5 % height quantile) at z = 0 and its side at one unit.
        const RoiFrame f = tiling.frame(k, members);
        size_t below = 0;
        for (uint32_t g : members) {
            const glm::vec3 q = f.map(glm::dvec3(s.positions[g]));
            REQUIRE(std::abs(q.x) <= 0.5f + 1e-4f);
            REQUIRE(std::abs(q.y) <= 0.5f + 1e-4f);
            below += q.z < -1e-6f;
        }
        REQUIRE(below <= size_t(0.05 * double(members.size())) + 1);
    }
    CHECK(std::all_of(count.begin(), count.end(), [](int c) { return c == 4; }));
    CHECK_THROWS_AS(semantic::SceneTiling(s.positions, up, 0.0), std::invalid_argument);
}

TEST_CASE("semantic samples: a tile column's batch with the scene's classes and features, as inference frames it") {
    std::vector<SemanticScene> scenes{random_scene(20000, 200.0, 3)};
    train::SemanticOptions o;
    o.max_points = 1000;
    o.tile = 40.0;
    const train::SemanticDrawer plain(scenes, 2, o.without_augmentation());
    const train::SemanticDrawer augmented(scenes, 2, o);
    for (int i = 0; i < 20; ++i) {
        Rng rng{uint64_t(i)}, again{uint64_t(i)};
        const auto s = plain.draw(rng);
        REQUIRE(s.size() > 0);
        REQUIRE(s.size() <= o.max_points);
        // ceil(n / batches) of the column, as the pipeline's partition takes.
        const size_t batches = (s.column_points + o.max_points - 1) / o.max_points;
        REQUIRE(s.size() == (s.column_points + batches - 1) / batches);
        const auto& sc = scenes[0];
        float zmin = 1e9f;
        for (size_t k = 0; k < s.size(); ++k) {
            const uint32_t g = s.gaussians[k];
            REQUIRE(s.labels[k] == sc.classes[g]);
            REQUIRE(s.feat[k] == sc.features[g]);
            zmin = std::min(zmin, s.coord[3 * k + 2]);
            // Heights are in tiles above the column's ground, unaugmented here.
            REQUIRE(std::abs(s.coord[3 * k + 2] * float(o.tile) - (sc.positions[g].z - (sc.positions[s.gaussians[0]].z -
                                                                                         s.coord[2] * float(o.tile)))) < 1e-3f);
        }
        REQUIRE(zmin < 0.0f);
        const auto t = plain.draw(again);
        REQUIRE(t.gaussians == s.gaussians);  // the same generator state, the same sample
        const auto a = augmented.draw(rng);
        REQUIRE(a.coord.size() == 3 * a.size());
    }
    std::vector<SemanticScene> bad{random_scene(100, 10.0, 1)};
    bad[0].classes[5] = 7;
    CHECK_THROWS(train::SemanticDrawer(bad, 2, o));
}

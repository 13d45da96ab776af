// Training samples (dataset/train/sample_drawer): labels, the ROI column, the first click's
// placement, batch-sized subsets, click-weight features, later clicks by the benchmark
// protocol, augmentation and determinism, feature groups after the click weights, on hand-made
// clouds and the sample desk scene.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <vector>

#include "dataset/error.h"
#include "dataset/formats/scene_io.h"
#include "dataset/random.h"
#include "dataset/semantic/gaussian_features.h"
#include "dataset/train/first_click.h"
#include "dataset/train/sample_drawer.h"
#include "tests/test_paths.h"

using namespace pg::data::train;
using pg::data::InputError;
using pg::data::Rng;

namespace {

// Up is -y. A 4 x 4 ground grid (instance 0) at spacing 0.04, a 0.4 box of Gaussians on it
// (instance 1), a second box off to the side (instance 3) and a 10-Gaussian speck
// (instance 2, below min_object_points).
TrainScene hand_scene(bool cameras) {
    TrainScene s;
    s.name = "hand";
    s.up = {0, -1, 0};
    auto add = [&](glm::vec3 p, int32_t id) {
        s.positions.push_back(p);
        s.instance.push_back(id);
    };
    for (int i = -50; i <= 50; ++i)
        for (int k = -50; k <= 50; ++k) add({0.04f * i, 0.0f, 0.04f * k}, 0);
    for (int i = 0; i < 10; ++i)
        for (int j = 1; j <= 10; ++j)
            for (int k = 0; k < 10; ++k) add({0.04f * i - 0.18f, -0.04f * j, 0.04f * k - 0.18f}, 1);
    for (int i = 0; i < 6; ++i)
        for (int j = 1; j <= 6; ++j)
            for (int k = 0; k < 6; ++k) add({0.04f * i + 0.8f, -0.04f * j, 0.04f * k + 0.8f}, 3);
    for (int i = 0; i < 10; ++i) add({-1.5f + 0.01f * i, -0.3f, -1.5f}, 2);
    if (cameras)  // a ring at distance ~4 from the origin: scale ~1
        for (int c = 0; c < 12; ++c) {
            const double a = 6.283185307179586 * c / 12;
            s.camera_positions.push_back({3.5 * std::cos(a), -2.0, 3.5 * std::sin(a)});
        }
    return s;
}

const TrainScene& desk_scene() {
    static const TrainScene s = load_train_scene(pg::test::source_dir() / "assets" / "sample" / "desk_000");
    return s;
}

// Capped distance from each member of `object` to the nearest non-member, by brute force.
std::vector<double> brute_depths(const TrainScene& s, int32_t id, const std::vector<uint32_t>& members, double cap) {
    std::vector<double> d(members.size(), cap);
    for (size_t m = 0; m < members.size(); ++m)
        for (size_t j = 0; j < s.size(); ++j)
            if (s.instance[j] != id)
                d[m] = std::min(d[m], double(glm::length(s.positions[members[m]] - s.positions[j])));
    return d;
}

float expected_weight(const Sample& s, size_t i, bool positive) {
    float w = 0;
    for (const TrainClick& c : s.clicks)
        if (c.positive == positive) {
            const glm::vec3 d = s.position[i] - c.position;
            w = std::max(w, std::exp(-glm::dot(d, d) / (2.0f * s.sigma * s.sigma)));
        }
    return w;
}

void check_features(const Sample& s) {
    REQUIRE(s.feat.size() == 2 * s.size());
    for (size_t i = 0; i < s.size(); ++i) {
        REQUIRE(s.feat[2 * i] == Approx(expected_weight(s, i, true)).margin(1e-6));
        REQUIRE(s.feat[2 * i + 1] == Approx(expected_weight(s, i, false)).margin(1e-6));
    }
}

void check_labels(const SampleDrawer& drawer, const Sample& s) {
    const TrainScene& scene = drawer.scenes()[s.scene];
    REQUIRE(s.labels.size() == s.size());
    REQUIRE(std::is_sorted(s.gaussians.begin(), s.gaussians.end()));
    REQUIRE(std::adjacent_find(s.gaussians.begin(), s.gaussians.end()) == s.gaussians.end());
    for (size_t i = 0; i < s.size(); ++i)
        REQUIRE(s.labels[i] == (scene.instance[s.gaussians[i]] == s.object ? 1 : 0));
}

}  // namespace

TEST_CASE("train: labels mark the drawn object, small objects are never drawn", "[train]") {
    const SampleDrawer drawer({hand_scene(true)});
    CHECK(drawer.object_count() == 2);
    Rng rng(1);
    std::set<int32_t> seen;
    for (int t = 0; t < 40; ++t) {
        const Sample s = drawer.draw(rng);
        seen.insert(s.object);
        check_labels(drawer, s);
        CHECK(std::count(s.labels.begin(), s.labels.end(), 1) > 0);
        CHECK(s.coord.size() == 3 * s.size());
    }
    CHECK(seen == std::set<int32_t>{1, 3});
}

TEST_CASE("train: without augmentation the sample is the whole ROI column in the frame", "[train]") {
    const TrainScene scene = hand_scene(true);
    const SampleOptions options = SampleOptions{}.without_augmentation();
    const SampleDrawer drawer({scene}, options);
    Rng rng(2);
    for (int t = 0; t < 20; ++t) {
        const Sample s = drawer.draw(rng);
        CHECK(s.roi.x >= 1.8f);
        CHECK(s.roi.x <= 3.2f);
        CHECK(s.roi.y >= 1.8f);
        CHECK(s.roi.y <= 3.2f);
        CHECK(s.sigma == Approx(0.4f));
        CHECK(s.augment == glm::mat3(1.0f));
        // The scale the pipeline would use: a quarter of the median camera distance.
        std::vector<double> d;
        for (auto& c : scene.camera_positions) d.push_back(glm::length(c - s.frame.centre));
        std::sort(d.begin(), d.end());
        CHECK(s.frame.scale == Approx(0.25 * d[d.size() / 2]));
        CHECK(glm::dot(s.frame.up, glm::dvec3(0, -1, 0)) == Approx(1.0));

        const float ground_z = float(s.frame.centre.y / s.frame.scale);
        CHECK(ground_z < 0.0f);
        size_t inside = 0;
        for (size_t i = 0; i < scene.size(); ++i) {
            const glm::vec3 q = s.frame.map(glm::dvec3(scene.positions[i]));
            inside += std::abs(q.x) <= 0.5f * s.roi.x && std::abs(q.y) <= 0.5f * s.roi.y;
        }
        CHECK(s.roi_points == inside);
        REQUIRE(s.size() == inside);  // fewer than max_points: nothing dropped
        for (size_t i = 0; i < s.size(); ++i) {
            const glm::vec3 c(s.coord[3 * i], s.coord[3 * i + 1], s.coord[3 * i + 2]);
            REQUIRE(c == s.position[i]);
            REQUIRE(std::abs(c.x) <= 0.5f * s.roi.x);
            REQUIRE(std::abs(c.y) <= 0.5f * s.roi.y);
            const glm::vec3 expect = s.frame.map(glm::dvec3(scene.positions[s.gaussians[i]]));
            REQUIRE(glm::length(c - expect) < 1e-6f);
            // Up is +z: the ground (world y = 0) lies level below the clicked box point.
            if (scene.instance[s.gaussians[i]] == 0) REQUIRE(c.z == Approx(ground_z).margin(1e-5));
            else REQUIRE(c.z > ground_z);
        }
    }
}

TEST_CASE("train: the first click is inside the object, away from its boundary, and varies", "[train]") {
    const TrainScene scene = hand_scene(false);
    const SampleDrawer drawer({scene}, SampleOptions{}.without_augmentation());
    // Brute-force depths of the big box (instance 1): the cap is half its 0.36 side.
    std::vector<uint32_t> members;
    for (uint32_t i = 0; i < scene.size(); ++i)
        if (scene.instance[i] == 1) members.push_back(i);
    const std::vector<double> depth = brute_depths(scene, 1, members, 0.18);
    const double deepest = *std::max_element(depth.begin(), depth.end());

    Rng rng(3);
    std::set<uint32_t> clicked;
    for (int t = 0; t < 60; ++t) {
        const Sample s = drawer.draw(rng);
        REQUIRE(!s.clicks.empty());
        const TrainClick& c = s.clicks[0];
        CHECK(c.positive);
        CHECK(c.position == glm::vec3(0.0f));
        CHECK(scene.instance[c.gaussian] == s.object);
        CHECK(glm::length(s.frame.centre - glm::dvec3(scene.positions[c.gaussian])) == 0.0);
        if (s.object != 1) continue;
        clicked.insert(c.gaussian);
        const size_t m = size_t(std::lower_bound(members.begin(), members.end(), c.gaussian) - members.begin());
        CHECK(depth[m] >= 0.5 * deepest - 1e-6);
        CHECK(depth[m] > 0.05);  // not on the box's contact with the ground
        // Without cameras the scale is the object's horizontal extent (0.36).
        CHECK(s.frame.scale == Approx(0.36).epsilon(1e-5));
    }
    CHECK(clicked.size() > 5);

    // The candidate set against brute force.
    std::vector<uint8_t> mask(scene.size());
    for (size_t i = 0; i < scene.size(); ++i) mask[i] = scene.instance[i] == 1;
    const FirstClickSet set = first_click_set(scene.positions, mask, 0.12f);
    REQUIRE(set.part == members);
    for (size_t m = 0; m < members.size(); ++m) REQUIRE(double(set.depth[m]) == Approx(depth[m]).margin(1e-6));
    size_t expected = 0;
    for (double d : depth) expected += d >= 0.5 * deepest - 1e-7;
    CHECK(set.candidates.size() == expected);
    CHECK(set.candidates.size() < members.size());
}

TEST_CASE("train: ROIs larger than max_points keep one partition batch's worth", "[train]") {
    SampleOptions o = SampleOptions{}.without_augmentation();
    o.max_points = 1000;
    const TrainScene scene = hand_scene(true);
    const SampleDrawer drawer({scene}, o);
    Rng rng(4);
    double roi_fraction = 0, sample_fraction = 0;
    for (int t = 0; t < 30; ++t) {
        const Sample s = drawer.draw(rng);
        REQUIRE(s.roi_points > o.max_points);
        const size_t batches = (s.roi_points + o.max_points - 1) / o.max_points;
        CHECK(s.size() == (s.roi_points + batches - 1) / batches);
        CHECK(s.size() <= o.max_points);
        check_labels(drawer, s);
        check_features(s);
        // The object is not favoured: its share of the batch is its share of the ROI.
        size_t roi_object = 0;
        for (size_t i = 0; i < scene.size(); ++i) {
            const glm::vec3 q = s.frame.map(glm::dvec3(scene.positions[i]));
            roi_object += scene.instance[i] == s.object && std::abs(q.x) <= 0.5f * s.roi.x &&
                          std::abs(q.y) <= 0.5f * s.roi.y;
        }
        roi_fraction += double(roi_object) / double(s.roi_points);
        sample_fraction += double(std::count(s.labels.begin(), s.labels.end(), 1)) / double(s.size());
    }
    CHECK(sample_fraction == Approx(roi_fraction).epsilon(0.1));

    // One point per batch at most: max_points = 1 gives single-point samples.
    o.max_points = 1;
    const SampleDrawer single({scene}, o);
    CHECK(single.draw(rng).size() == 1);
}

TEST_CASE("train: features are the pipeline's Gaussian click weights", "[train]") {
    const SampleDrawer drawer({hand_scene(true)});
    Rng rng(5);
    for (int t = 0; t < 10; ++t) {
        const Sample s = drawer.draw(rng);
        check_features(s);
        // In world units: exp(-|mu - p|^2 / (2 (0.4 scale)^2)), the prompt encoder's formula.
        const TrainScene& scene = drawer.scenes()[s.scene];
        const double sigma = 0.4 * s.frame.scale;
        for (size_t i = 0; i < s.size(); i += 7) {
            const glm::dvec3 d = glm::dvec3(scene.positions[s.gaussians[i]]) - s.frame.centre;
            REQUIRE(double(s.feat[2 * i]) == Approx(std::exp(-glm::dot(d, d) / (2 * sigma * sigma))).margin(1e-5));
            REQUIRE(s.feat[2 * i + 1] == 0.0f);
        }
    }
}

TEST_CASE("train: add_click follows the benchmark protocol and reweights", "[train]") {
    const SampleDrawer drawer({hand_scene(true)});
    Rng rng(6);
    Sample s = drawer.draw(rng);
    std::vector<uint8_t> truth(s.size());
    for (size_t i = 0; i < s.size(); ++i) truth[i] = uint8_t(s.labels[i]);

    // The prediction is right: no click, nothing changes.
    const std::vector<float> before = s.feat;
    CHECK_FALSE(drawer.add_click(s, truth));
    CHECK(s.clicks.size() == 1);
    CHECK(s.feat == before);

    // Everything missed: a positive click on the object.
    Sample missed = s;
    REQUIRE(drawer.add_click(missed, std::vector<uint8_t>(s.size(), 0)));
    REQUIRE(missed.clicks.size() == 2);
    CHECK(missed.clicks[1].positive);
    const auto at = std::find(missed.gaussians.begin(), missed.gaussians.end(), missed.clicks[1].gaussian);
    REQUIRE(at != missed.gaussians.end());
    CHECK(missed.labels[size_t(at - missed.gaussians.begin())] == 1);
    check_features(missed);

    // The object and a block of ground taken too: a negative click on the wrong block.
    std::vector<uint8_t> too_much = truth;
    size_t wrong = 0;
    for (size_t i = 0; i < s.size(); ++i)
        if (!s.labels[i] && s.position[i].x > 0.3f * s.roi.x) too_much[i] = 1, ++wrong;
    REQUIRE(wrong > 50);
    Sample over = s;
    REQUIRE(drawer.add_click(over, too_much));
    const TrainClick& neg = over.clicks.back();
    CHECK_FALSE(neg.positive);
    const size_t k = size_t(std::find(over.gaussians.begin(), over.gaussians.end(), neg.gaussian) - over.gaussians.begin());
    REQUIRE(k < over.size());
    CHECK(over.labels[k] == 0);
    CHECK(too_much[k] == 1);
    CHECK(neg.position == over.position[k]);
    check_features(over);
    CHECK(over.feat[2 * k + 1] == Approx(1.0f));

    CHECK_THROWS_AS(drawer.add_click(s, std::vector<uint8_t>(3, 0)), InputError);
}

TEST_CASE("train: augmentation moves only the coordinates, within its bounds", "[train]") {
    const SampleDrawer drawer({hand_scene(true)});
    Rng rng(8);
    std::set<bool> flipped;
    for (int t = 0; t < 30; ++t) {
        const Sample s = drawer.draw(rng);
        const glm::mat3& m = s.augment;
        // Rotation about up, flips of x/y and an isotropic scale: z stays z.
        const float k = std::abs(m[2][2]);
        CHECK(k >= 0.9f);
        CHECK(k <= 1.1f);
        CHECK(m[2][2] > 0);
        CHECK(m[0][2] == 0.0f);
        CHECK(m[1][2] == 0.0f);
        CHECK(m[2][0] == 0.0f);
        CHECK(m[2][1] == 0.0f);
        CHECK(std::abs(glm::determinant(m)) == Approx(k * k * k).epsilon(1e-4));
        flipped.insert(glm::determinant(m) < 0);
        for (size_t i = 0; i < s.size(); ++i) {
            const glm::vec3 p = s.augmented(s.position[i]);
            for (int a = 0; a < 3; ++a) REQUIRE(std::abs(s.coord[3 * i + a] - p[a]) <= 0.01f + 1e-5f);
        }
        check_features(s);  // features stay those of the un-augmented geometry
    }
    CHECK(flipped.size() == 2);
}

TEST_CASE("train: samples are deterministic per seed", "[train]") {
    const SampleDrawer drawer({hand_scene(true), hand_scene(false)});
    Rng a(42), b(42), c(43);
    for (int t = 0; t < 5; ++t) {
        const Sample x = drawer.draw(a), y = drawer.draw(b), z = drawer.draw(c);
        CHECK(x.scene == y.scene);
        CHECK(x.gaussians == y.gaussians);
        CHECK(x.coord == y.coord);
        CHECK(x.feat == y.feat);
        CHECK(x.labels == y.labels);
        CHECK(x.coord != z.coord);
    }
}

TEST_CASE("train: options and scenes without drawable objects are refused", "[train]") {
    TrainScene speck = hand_scene(false);
    for (int32_t& id : speck.instance) id = id == 2 ? 2 : 0;
    CHECK_THROWS_AS(SampleDrawer({speck}), InputError);
    CHECK_THROWS_AS(SampleDrawer({}), InputError);
    SampleOptions bad;
    bad.roi_min = 4.0;
    CHECK_THROWS_AS(SampleDrawer({hand_scene(false)}, bad), std::invalid_argument);
}

TEST_CASE("train: samples of the sample desk scene", "[train]") {
    const SampleDrawer drawer({desk_scene()});
    CHECK(drawer.object_count() >= 10);
    Rng rng(9);
    for (int t = 0; t < 10; ++t) {
        Sample s = drawer.draw(rng);
        CHECK(s.size() > 100);
        CHECK(s.size() <= 8192);
        check_labels(drawer, s);
        check_features(s);
        CHECK(desk_scene().instance[s.clicks[0].gaussian] == s.object);
        // A ROI of 1.8 to 3.2 x the scale (0.25 x the cameras' median distance) around the click.
        CHECK(s.frame.scale > 0.05);
        CHECK(s.frame.scale < 0.5);
        // The protocol's second click on an all-background prediction is positive.
        REQUIRE(drawer.add_click(s, std::vector<uint8_t>(s.size(), 0)));
        CHECK(s.clicks.back().positive);
    }
}

TEST_CASE("train: feature groups follow the click weights, in the model's voxel, and colour augmentation keeps them in range",
          "[train]") {
    namespace sem = pg::data::semantic;
    const auto groups = sem::all_feature_groups();
    const auto dir = pg::test::source_dir() / "assets" / "sample" / "desk_000";
    const TrainScene scene = load_train_scene(dir, std::nullopt, groups);
    const pg::data::GaussianCloud cloud = pg::data::load_scene(dir / "scene.ply");
    REQUIRE(scene.features.size() == 8 * scene.size());
    SampleOptions o = SampleOptions{}.without_augmentation();
    o.features = groups;
    o.voxel = 0.02;
    const SampleDrawer plain({scene}, o);
    Rng rng(11);
    Sample s = plain.draw(rng);
    REQUIRE(s.feat.size() == 10 * s.size());
    // What the decoder computes at inference for these Gaussians in this frame (ptv3_decoder.cpp).
    std::vector<float> expect = sem::raw_gaussian_features(cloud, s.gaussians, groups, s.frame.up);
    sem::finish_gaussian_features(expect, groups, 0.02 * s.frame.scale);
    for (size_t i = 0; i < s.size(); ++i)
        for (size_t c = 0; c < 8; ++c) REQUIRE(s.feat[10 * i + 2 + c] == Approx(expect[8 * i + c]).margin(1e-6));
    // A later click recomputes the click weights and keeps the appearance.
    std::vector<uint8_t> nothing(s.size(), 0);
    REQUIRE(plain.add_click(s, nothing));
    for (size_t i = 0; i < s.size(); i += 5) REQUIRE(s.feat[10 * i + 2] == Approx(expect[8 * i]).margin(1e-6));
    // Other groups than rgb are never augmented; rgb stays in [0, 1] and changes.
    SampleOptions a = o;
    a.colour = true;
    const SampleDrawer coloured({scene}, a);
    Rng r1(11), r2(11);
    const Sample t = coloured.draw(r1);
    REQUIRE(t.gaussians == plain.draw(r2).gaussians);
    bool changed = false;
    for (size_t i = 0; i < t.size(); ++i) {
        for (size_t c = 0; c < 3; ++c) {
            const float v = t.feat[10 * i + 2 + c];
            REQUIRE(v >= 0.0f);
            REQUIRE(v <= 1.0f);
            changed = changed || std::abs(v - expect[8 * i + c]) > 1e-4f;
        }
        for (size_t c = 3; c < 8; ++c) REQUIRE(t.feat[10 * i + 2 + c] == Approx(expect[8 * i + c]).margin(1e-6));
    }
    CHECK(changed);
    // A model's scale_spacing raises the log scales as the decoder does, only below it.
    std::vector<glm::vec3> world;
    for (uint32_t g : s.gaussians) world.push_back(cloud.mean[g]);
    const float k = sem::scale_spacing(expect, groups, world, 0.02 * s.frame.scale);
    REQUIRE(std::isfinite(k));
    for (const float margin : {-0.5f, 0.5f}) {
        SampleOptions r = o;
        r.scale_spacing = k + margin;
        const SampleDrawer raised({scene}, r);
        Rng r3(11);
        const Sample u = raised.draw(r3);
        REQUIRE(u.gaussians == s.gaussians);
        for (size_t i = 0; i < u.size(); ++i)
            for (size_t c = 0; c < 8; ++c)
                REQUIRE(u.feat[10 * i + 2 + c] ==
                        Approx(expect[8 * i + c] + (c >= 4 && c < 7 && margin > 0 ? margin : 0.0f)).margin(1e-5));
    }
    // Scenes loaded with other groups than the drawer's are refused.
    CHECK_THROWS_AS(SampleDrawer({load_train_scene(dir)}, o), std::invalid_argument);
    CHECK_THROWS_AS(SampleDrawer({scene}, SampleOptions{}), std::invalid_argument);
}

// label_by_class against a rule the test knows: a fake class network that labels a point by
// its height in the tile frame and its colour, so the tiling, packing and voting are checked
// without a trained model.
#include <algorithm>
#include <cmath>

#include <catch2/catch.hpp>

#include "dataset/random.h"
#include "engine/segment/semantic_labeler.h"

using namespace pg;

namespace {

// Class 2 for red Gaussians, else 1 above a tenth of a tile over the ground, else 0.
class HeightNetwork : public seg::ClassNetwork {
public:
    int classes() const override { return 3; }
    double tile_size() const override { return 10.0; }
    double voxel() const override { return 0.1; }
    std::vector<std::string> features() const override { return {"rgb", "opacity"}; }
    std::vector<float> probabilities(const std::vector<seg::ClassCloud>& clouds) override {
        ++calls;
        std::vector<float> p;
        for (const auto& c : clouds) {
            REQUIRE(c.size() <= 500);
            REQUIRE(c.feat.size() == 4 * c.size());
            points += c.size();
            for (size_t i = 0; i < c.size(); ++i) {
                const int cls = c.feat[4 * i] > 0.8f ? 2 : (c.coord[3 * i + 2] > 0.1f ? 1 : 0);
                for (int k = 0; k < 3; ++k) p.push_back(k == cls ? 0.9f : 0.05f);
            }
        }
        return p;
    }
    size_t calls = 0, points = 0;
};

}  // namespace

TEST_CASE("semantic labeler: four tiles vote for every Gaussian and packed forwards keep each point's row") {
    data::Rng rng(5);
    data::GaussianCloud cloud;
    const size_t n = 6000;
    cloud.resize(n);
    std::vector<int> expect(n);
    for (size_t i = 0; i < n; ++i) {
        // A flat ground at z = 0 (two thirds) and posts up to 5 m; every tenth red.
        const bool post = i % 3 == 0;
        cloud.mean[i] = glm::vec3(float(rng.uniform(0, 40)), float(rng.uniform(0, 40)), post ? float(rng.uniform(2.5, 5)) : 0.0f);
        const bool red = i % 10 == 1;
        cloud.sh[3 * i] = red ? 3.0f : -1.0f;
        expect[i] = red ? 2 : (post ? 1 : 0);
    }
    cloud.mean[7] = glm::vec3(NAN, 0, 0);
    expect[7] = 0;
    HeightNetwork net;
    seg::SemanticLabelOptions o;
    o.max_batch = 500;
    o.forward_points = 2000;
    size_t last_done = 0;
    o.progress = [&](size_t done, size_t total) {
        REQUIRE(done >= last_done);
        REQUIRE(done <= total);
        last_done = done;
    };
    const auto r = seg::label_by_class(cloud, net, o);
    CHECK(r.classes == expect);
    CHECK(r.unvoted == 1);
    CHECK(net.points == 4 * (n - 1));  // every finite Gaussian in four tiles
    CHECK(r.forwards == net.calls);
    CHECK(r.forwards >= 4 * (n - 1) / 2000);
    CHECK(r.class_counts[1] == size_t(std::count(expect.begin(), expect.end(), 1)));
    CHECK(r.confidence[0] > 0.85f);
    CHECK(last_done == r.tiles);

    o.up = glm::dvec3(0.0);
    CHECK_THROWS_AS(seg::label_by_class(cloud, net, o), std::invalid_argument);
}

// Class labels in the viewer: class names and numbers, and the regions of a class an object
// is made from (all of it, or the connected part under a click).
#include <catch2/catch.hpp>

#include <stdexcept>

#include "app/viewer/class_labels.h"

using namespace pg::viewer;

namespace {

// Class 1 in two rows of points 0.1 apart, 4 units from each other; class 2 between them.
struct Scene {
    std::vector<glm::vec3> means;
    ClassLabels labels;
    Scene() {
        labels.names = {"other", "building", "road"};
        auto add = [&](glm::vec3 p, int c, float confidence) {
            means.push_back(p);
            labels.classes.push_back(c);
            labels.confidence.push_back(confidence);
        };
        for (int i = 0; i < 10; ++i) add({0.1f * float(i), 0, 0}, 1, 0.8f);   // 0..9
        for (int i = 0; i < 12; ++i) add({5 + 0.1f * float(i), 0, 0}, 1, 0.6f);  // 10..21
        for (int i = 0; i < 5; ++i) add({2.5f, 0.1f * float(i), 0}, 2, 0.0f);   // 22..26
        labels.counts = {0, 22, 5};
    }
};

}  // namespace

TEST_CASE("classes are found by name or number, and unnamed ones get a name", "[viewer]") {
    Scene s;
    CHECK(s.labels.find("building") == 1);
    CHECK(s.labels.find("2") == 2);
    CHECK(s.labels.find("3") == -1);
    CHECK(s.labels.find("bridge") == -1);
    CHECK(s.labels.name(7) == "class_7");
}

TEST_CASE("an object's region is a whole class, or the connected part of it under a click", "[viewer]") {
    Scene s;
    auto whole = class_region(s.means, s.labels, 1);
    CHECK(whole->gaussians.size() == 22);
    CHECK(whole->source == "class building");
    CHECK(whole->probability[0] == Approx(0.8f));

    auto left = class_region(s.means, s.labels, 1, 3);
    REQUIRE(left->gaussians.size() == 10);
    CHECK(left->gaussians.front() == 0);
    CHECK(left->gaussians.back() == 9);
    CHECK(left->source == "class building (connected region)");
    auto right = class_region(s.means, s.labels, 1, 15);
    CHECK(right->gaussians.size() == 12);
    CHECK(right->probability[0] == Approx(0.6f));

    // No vote still claims (a claim of 0 would label nothing).
    auto road = class_region(s.means, s.labels, 2, 22);
    REQUIRE(road->gaussians.size() == 5);
    CHECK(road->probability[0] > 0.0f);

    CHECK_THROWS_AS(class_region(s.means, s.labels, 1, 22), std::invalid_argument);
}

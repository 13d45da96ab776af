// The free camera: poses round-trip, the image's up is the scene's up, and each control
// moves what it should.
#include <catch2/catch.hpp>

#include <glm/gtc/epsilon.hpp>

#include "app/viewer/orbit_camera.h"
#include "dataset/orbit.h"

using namespace pg::viewer;

namespace {
bool near(glm::dvec3 a, glm::dvec3 b, double eps = 1e-9) { return glm::length(a - b) < eps; }
// Pixel of a world point.
glm::dvec2 project(const pg::data::Camera& c, glm::dvec3 x) {
    glm::dvec3 p = c.R * x + c.t;
    return {c.fx * p.x / p.z + c.cx, c.fy * p.y / p.z + c.cy};
}
}  // namespace

TEST_CASE("look_at puts the target at the image centre with the scene's up pointing up", "[viewer]") {
    for (glm::dvec3 up : {glm::dvec3(0, -1, 0), glm::dvec3(0, 0, 1), glm::normalize(glm::dvec3(0.2, 1, 0.1))}) {
        OrbitCamera cam(up);
        const glm::dvec3 target(0.3, -0.2, 1.5), eye(2.0, 0.5, -1.0);
        cam.look_at(eye, target);
        REQUIRE(near(cam.target(), target));
        const auto c = cam.camera(640, 480, 50);
        const glm::dvec2 centre = project(c, target);
        REQUIRE(std::abs(centre.x - 320) < 1e-6);
        REQUIRE(std::abs(centre.y - 240) < 1e-6);
        // A point above the target appears higher in the image (smaller row).
        REQUIRE(project(c, target + 0.1 * up).y < 240);
        REQUIRE(std::abs(glm::length(cam.eye() - target) - glm::length(eye - target)) < 1e-9);
        // Vertical field of view as asked.
        REQUIRE(std::abs(2 * std::atan(240.0 / c.fy) - glm::radians(50.0)) < 1e-9);
    }
}

TEST_CASE("orbit keeps the target and distance, pan moves both eye and target sideways", "[viewer]") {
    OrbitCamera cam({0, -1, 0});
    cam.look_at({0, -1, -4}, {0, 0, 0});
    const double d = cam.distance();
    cam.orbit(35, 10);
    REQUIRE(near(cam.target(), {0, 0, 0}));
    REQUIRE(std::abs(glm::length(cam.eye()) - d) < 1e-9);
    const glm::dvec3 f = cam.forward();
    cam.pan(0.1, 0.0);
    REQUIRE(std::abs(glm::length(cam.target()) - 0.1 * d) < 1e-9);
    REQUIRE(std::abs(glm::dot(cam.target(), f)) < 1e-9);  // in the view plane
    REQUIRE(near(cam.forward(), f));
    cam.dolly(0.5);
    REQUIRE(std::abs(cam.distance() - 0.5 * d) < 1e-9);
    // Pitch stops short of the pole, where the horizon would be undefined.
    cam.orbit(0, 500);
    const auto c = cam.camera(100, 100, 60);
    REQUIRE(std::isfinite(c.R[0][0]));
    REQUIRE(glm::dot(cam.forward(), glm::dvec3(0, -1, 0)) > -1.0);
}

TEST_CASE("fly moves eye and target together along the view", "[viewer]") {
    OrbitCamera cam({0, 0, 1});
    cam.look_at({-3, 0, 0}, {0, 0, 0});
    const glm::dvec3 eye = cam.eye();
    cam.fly({0, 0, 0.5});  // forward by half the distance
    REQUIRE(near(cam.eye(), eye + glm::dvec3(1.5, 0, 0)));
    REQUIRE(near(cam.target(), {1.5, 0, 0}));
}

TEST_CASE("matching a dataset camera keeps its position and viewing direction", "[viewer]") {
    const glm::dvec3 up(0, -1, 0);
    auto ds = pg::data::look_at("view", {1, -2, -3}, {0.2, 0.1, 0.4}, up, 320, 240, 60);
    OrbitCamera cam(up);
    cam.match(ds, 2.5);
    REQUIRE(near(cam.eye(), ds.position(), 1e-9));
    REQUIRE(near(cam.forward(), ds.forward(), 1e-9));
    REQUIRE(std::abs(cam.distance() - 2.5) < 1e-9);
}

// The bundled sample scene generator: deterministic, finite, labelled, and framed by its cameras.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <set>

#include "dataset/sample_scene.h"

using pg::data::make_sample_scene;
using pg::data::SampleScene;

namespace {

template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

}  // namespace

TEST_CASE("sample scene is deterministic for a seed", "[sample]") {
    const SampleScene a = make_sample_scene(1), b = make_sample_scene(1), c = make_sample_scene(2);
    CHECK(same_bytes(a.cloud.mean, b.cloud.mean));
    CHECK(same_bytes(a.cloud.log_scale, b.cloud.log_scale));
    CHECK(same_bytes(a.cloud.rotation, b.cloud.rotation));
    CHECK(same_bytes(a.cloud.opacity_logit, b.cloud.opacity_logit));
    CHECK(same_bytes(a.cloud.sh, b.cloud.sh));
    CHECK(a.cloud.int_property("instance") == b.cloud.int_property("instance"));
    REQUIRE(a.cameras.size() == b.cameras.size());
    for (size_t i = 0; i < a.cameras.size(); ++i) {
        CHECK(a.cameras[i].R == b.cameras[i].R);
        CHECK(a.cameras[i].t == b.cameras[i].t);
    }
    CHECK_FALSE(same_bytes(a.cloud.mean, c.cloud.mean));
    CHECK_FALSE(same_bytes(a.cloud.sh, c.cloud.sh));
}

TEST_CASE("sample scene arrays are consistent and finite", "[sample]") {
    const SampleScene s = make_sample_scene();
    const auto& cloud = s.cloud;
    const size_t n = cloud.size();
    CHECK(n > 25000);
    CHECK(n < 40000);
    CHECK(cloud.sh_degree == 1);
    REQUIRE(cloud.log_scale.size() == n);
    REQUIRE(cloud.rotation.size() == n);
    REQUIRE(cloud.opacity_logit.size() == n);
    REQUIRE(cloud.sh.size() == n * 4 * 3);
    for (size_t i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k) {
            REQUIRE(std::isfinite(cloud.mean[i][k]));
            REQUIRE(std::isfinite(cloud.log_scale[i][k]));
        }
        REQUIRE(glm::length(cloud.rotation[i]) > 0.5f);
        REQUIRE(std::isfinite(cloud.opacity_logit[i]));
        // Surface-aligned: one axis much thinner than the other two.
        const glm::vec3 s3 = glm::exp(cloud.log_scale[i]);
        REQUIRE(s3.z < 0.5f * std::min(s3.x, s3.y));
    }
    for (float v : cloud.sh) REQUIRE(std::isfinite(v));
    // Most Gaussians are nearly opaque, with a low tail.
    size_t opaque = 0, faint = 0;
    for (float l : cloud.opacity_logit) {
        const float o = 1.0f / (1.0f + std::exp(-l));
        if (o > 0.9f) ++opaque;
        if (o < 0.5f) ++faint;
    }
    CHECK(opaque > n * 3 / 4);
    CHECK(faint > n / 50);
}

TEST_CASE("sample scene instance labels cover the table and every object", "[sample]") {
    const SampleScene s = make_sample_scene();
    const auto labels = s.cloud.int_property("instance");
    REQUIRE(labels);
    REQUIRE(labels->size() == s.cloud.size());
    std::set<int32_t> seen(labels->begin(), labels->end());
    std::set<int32_t> want;
    for (int k = 0; k <= pg::data::kSampleSceneObjects; ++k) want.insert(k);
    CHECK(seen == want);
    // Objects stand on the table top: above it (y <= 0, up is -y) and over it.
    for (size_t i = 0; i < s.cloud.size(); ++i) {
        if ((*labels)[i] == 0) continue;
        const glm::vec3 p = s.cloud.mean[i];
        REQUIRE(p.y < 0.005f);
        REQUIRE(std::abs(p.x) < 0.6f);
        REQUIRE(std::abs(p.z) < 0.4f);
    }
}

TEST_CASE("sample scene cameras look at the table", "[sample]") {
    const SampleScene s = make_sample_scene();
    REQUIRE(s.cameras.size() == 24);
    for (size_t i = 0; i < s.cameras.size(); ++i) {
        const auto& cam = s.cameras[i];
        CAPTURE(cam.name);
        char want[32];
        std::snprintf(want, sizeof want, "view_%03zu", i);
        CHECK(cam.name == want);
        CHECK(cam.width == 640);
        CHECK(cam.height == 480);
        // A rotation: orthonormal, right-handed.
        const glm::dmat3 rrt = cam.R * glm::transpose(cam.R);
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) REQUIRE(std::abs(rrt[c][r] - (r == c ? 1.0 : 0.0)) < 1e-9);
        CHECK(glm::determinant(cam.R) == Approx(1.0));
        // The table centre projects well inside the image, in front of the camera; from the
        // higher ring the nearest corners may fall just below the frame, so ask for two of four.
        auto project = [&](glm::dvec3 p) {
            const glm::dvec3 q = cam.R * p + cam.t;
            return glm::dvec3(cam.fx * q.x / q.z + cam.cx, cam.fy * q.y / q.z + cam.cy, q.z);
        };
        const glm::dvec3 centre = project(glm::dvec3(0.0));
        CHECK(centre.z > 1.0);
        CHECK(centre.x > 0.25 * cam.width);
        CHECK(centre.x < 0.75 * cam.width);
        CHECK(centre.y > 0.25 * cam.height);
        CHECK(centre.y < 0.75 * cam.height);
        int corners_inside = 0;
        for (glm::dvec3 p : {glm::dvec3(0.6, 0, 0.4), glm::dvec3(-0.6, 0, 0.4), glm::dvec3(0.6, 0, -0.4),
                             glm::dvec3(-0.6, 0, -0.4)}) {
            const glm::dvec3 q = project(p);
            REQUIRE(q.z > 0.5);
            if (q.x > 0 && q.x < cam.width && q.y > 0 && q.y < cam.height) ++corners_inside;
        }
        CHECK(corners_inside >= 2);
        // Image down is world down (+y); the cameras are above the table (y < 0).
        const glm::dvec3 cam_down_in_world = glm::transpose(cam.R)[1];
        CHECK(cam_down_in_world.y > 0.5);
        CHECK(cam.position().y < -0.5);
        CHECK(glm::length(cam.position()) == Approx(1.6));
    }
}

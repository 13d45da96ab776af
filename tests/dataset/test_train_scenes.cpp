// Training scenes (dataset/train): the network's RoiFrame, loading scene folders and bare
// PLYs with instance labels, expanding suites by split, and the errors for unusable input.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "dataset/error.h"
#include "dataset/formats/scene_io.h"
#include "dataset/random.h"
#include "dataset/roi_frame.h"
#include "dataset/train/train_scene.h"
#include "tests/test_paths.h"

namespace fs = std::filesystem;
using namespace pg::data::train;
using pg::data::InputError;
using pg::data::RoiFrame;

namespace {

fs::path fresh_scratch(const char* name) {
    const fs::path p = pg::test::scratch(name);
    fs::remove_all(p);
    fs::create_directories(p);
    return p;
}

fs::path desk() { return pg::test::source_dir() / "assets" / "sample" / "desk_000"; }

// A ground grid (y = 0, up = -y) and a 0.4 box standing on it; instances optional.
pg::data::GaussianCloud ground_and_box(bool with_instance, int object_id = 1) {
    pg::data::GaussianCloud c;
    std::vector<int32_t> ids;
    for (int i = -20; i <= 20; ++i)
        for (int k = -20; k <= 20; ++k) {
            c.mean.push_back({0.05f * i, 0.0f, 0.05f * k});
            ids.push_back(0);
        }
    for (int i = 0; i < 8; ++i)
        for (int j = 1; j <= 8; ++j)
            for (int k = 0; k < 8; ++k) {
                c.mean.push_back({0.05f * i - 0.175f, -0.05f * j, 0.05f * k - 0.175f});
                ids.push_back(object_id);
            }
    const std::vector<glm::vec3> means = c.mean;
    c.resize(means.size());
    c.mean = means;
    if (with_instance) c.set_int_property("instance", ids);
    return c;
}

std::string error_of(const fs::path& p) {
    try {
        load_train_scene(p);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_CASE("train: RoiFrame puts up on +z, divides by the scale and is right-handed", "[train]") {
    const glm::dvec3 centre(0.3, -1.2, 4.0);
    const RoiFrame f = RoiFrame::around(centre, {0, -2, 0}, 0.5);  // up need not be unit
    CHECK(f.map(centre) == glm::vec3(0.0f));
    const glm::vec3 above = f.map(centre + glm::dvec3(0, -1, 0));
    CHECK(above.x == Approx(0.0f).margin(1e-6));
    CHECK(above.y == Approx(0.0f).margin(1e-6));
    CHECK(above.z == Approx(2.0f));
    const glm::vec3 along = f.map(centre + 0.5 * f.length_axis);
    CHECK(along.x == Approx(1.0f));
    CHECK(f.map(centre + 0.25 * f.width_axis).y == Approx(0.5f));
    CHECK(glm::length(glm::cross(f.length_axis, f.width_axis) - f.up) < 1e-12);

    pg::data::Rng rng(7);
    for (int t = 0; t < 50; ++t) {
        const glm::dvec3 up = glm::normalize(glm::dvec3(rng.normal(), rng.normal(), rng.normal()));
        const RoiFrame g = RoiFrame::around({rng.normal(), rng.normal(), rng.normal()}, up, rng.uniform(0.1, 3.0));
        CHECK(std::abs(glm::dot(g.length_axis, g.up)) < 1e-12);
        CHECK(std::abs(glm::dot(g.width_axis, g.up)) < 1e-12);
        CHECK(glm::dot(glm::cross(g.length_axis, g.width_axis), g.up) == Approx(1.0));
        const glm::dvec3 p(rng.normal(), rng.normal(), rng.normal());
        const glm::vec3 q = g.map(p);
        CHECK(double(q.z) == Approx(glm::dot(p - g.centre, up) / g.scale).margin(1e-5));
        CHECK(glm::length(g.unmap(q) - p) < 1e-5);
        CHECK(double(glm::length(q)) == Approx(glm::length(p - g.centre) / g.scale).epsilon(1e-5));
    }
}

TEST_CASE("train: the sample desk scene loads with labels, cameras and up", "[train]") {
    const TrainScene s = load_train_scene(desk());
    CHECK(s.name == "desk_000");
    CHECK(s.source == desk() / "scene.ply");
    CHECK(s.size() == 54201);
    REQUIRE(s.instance.size() == s.size());
    CHECK(std::count_if(s.instance.begin(), s.instance.end(), [](int32_t id) { return id > 0; }) > 1000);
    CHECK(s.has_cameras());
    CHECK(glm::dot(s.up, glm::dvec3(0, -1, 0)) > 0.99);  // meta.json: up = -y
    // An explicit up wins.
    CHECK(load_train_scene(desk(), glm::dvec3(0, 0, 2)).up == glm::dvec3(0, 0, 1));
}

TEST_CASE("train: a bare PLY with instances loads without cameras, up from the ground", "[train]") {
    const fs::path dir = fresh_scratch("train_bare_ply");
    pg::data::write_ply(ground_and_box(true), dir / "box.ply");
    const TrainScene s = load_train_scene(dir / "box.ply");
    CHECK(s.name == "box");
    CHECK(!s.has_cameras());
    CHECK(s.size() == 41 * 41 + 512);
    CHECK(glm::dot(s.up, glm::dvec3(0, -1, 0)) > 0.999);
    CHECK(s.instance.back() == 1);

    // A scene folder without cameras is trained like a bare PLY.
    fs::create_directories(dir / "folder");
    fs::copy_file(dir / "box.ply", dir / "folder" / "scene.ply");
    const TrainScene f = load_train_scene(dir / "folder");
    CHECK(f.name == "folder");
    CHECK(!f.has_cameras());
    CHECK(f.positions == s.positions);
}

TEST_CASE("train: unusable scenes give one InputError naming the path and the reason", "[train]") {
    const fs::path dir = fresh_scratch("train_bad_scenes");
    pg::data::write_ply(ground_and_box(false), dir / "unlabelled.ply");
    const std::string no_instance = error_of(dir / "unlabelled.ply");
    CHECK_THAT(no_instance, Catch::Contains("unlabelled.ply") && Catch::Contains("instance"));

    pg::data::write_ply(ground_and_box(true, 0), dir / "background.ply");
    CHECK_THAT(error_of(dir / "background.ply"), Catch::Contains("background.ply") && Catch::Contains("no object"));

    std::ofstream(dir / "garbage.ply") << "this is not a PLY file\n";
    CHECK_THAT(error_of(dir / "garbage.ply"), Catch::Contains("garbage.ply"));

    CHECK_THAT(error_of(dir / "missing.ply"), Catch::Contains("missing.ply") && Catch::Contains("no such"));
    fs::create_directories(dir / "empty_folder");
    CHECK_THAT(error_of(dir / "empty_folder"), Catch::Contains("empty_folder") && Catch::Contains("scene.ply"));
}

TEST_CASE("train: find_train_scenes expands suites by split and keeps scenes and PLYs", "[train]") {
    const fs::path suite = pg::test::source_dir() / "assets" / "sample";
    CHECK(find_train_scenes({suite}, "train") == std::vector<fs::path>{suite / "desk_000"});
    CHECK(find_train_scenes({suite}, "test").empty());
    CHECK(find_train_scenes({suite}, "all") == std::vector<fs::path>{suite / "desk_000"});
    CHECK(find_train_scenes({desk(), suite}, "test") == std::vector<fs::path>{desk()});
    CHECK(find_train_scenes({desk() / "scene.ply"}, "train") == std::vector<fs::path>{desk() / "scene.ply"});
    CHECK_THROWS_WITH(find_train_scenes({suite}, "validation"), Catch::Contains("validation"));
    CHECK_THROWS_AS(find_train_scenes({suite}, "validation"), InputError);
    CHECK_THROWS_WITH(find_train_scenes({suite / "nowhere"}, "train"), Catch::Contains("nowhere"));
    CHECK_THROWS_WITH(find_train_scenes({desk() / "masks"}, "train"), Catch::Contains("masks"));
}

// Camera importers and writers: hand-checked poses per format, projection, round trips,
// every COLMAP model, the distortion warning and load_cameras' dispatch.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>

#include <catch2/catch.hpp>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include "dataset/error.h"
#include "dataset/formats/camera_io.h"
#include "tests/test_paths.h"

namespace fs = std::filesystem;
using pg::data::Camera;

namespace {

fs::path fresh_scratch(const char* name) {
    fs::remove_all(pg::test::binary_dir() / "test-scratch" / name);
    return pg::test::scratch(name);
}

void write_text(const fs::path& path, const std::string& text) {
    fs::create_directories(path.parent_path());
    std::ofstream(path, std::ios::binary) << text;
}

void write_bytes(const fs::path& path, const std::string& bytes) { write_text(path, bytes); }

template <class T>
void append(std::string& out, T v) {
    char buf[sizeof(T)];
    std::memcpy(buf, &v, sizeof(T));
    out.append(buf, sizeof(T));
}

// Captures std::cerr for the scope's lifetime.
struct CerrCapture {
    std::ostringstream text;
    std::streambuf* old = std::cerr.rdbuf(text.rdbuf());
    ~CerrCapture() { std::cerr.rdbuf(old); }
};

glm::dvec3 to_camera(const Camera& c, const glm::dvec3& world) { return c.R * world + c.t; }

glm::dvec2 project(const Camera& c, const glm::dvec3& world) {
    const glm::dvec3 p = to_camera(c, world);
    return {c.fx * p.x / p.z + c.cx, c.fy * p.y / p.z + c.cy};
}

void require_near(const glm::dmat3& a, const glm::dmat3& b, double eps = 1e-9) {
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) REQUIRE(a[c][r] == Approx(b[c][r]).margin(eps));
}

void require_near(const glm::dvec3& a, const glm::dvec3& b, double eps = 1e-9) {
    for (int i = 0; i < 3; ++i) REQUIRE(a[i] == Approx(b[i]).margin(eps));
}

void require_same(const Camera& a, const Camera& b, bool same_model = true) {
    INFO("camera " << a.name);
    REQUIRE(a.name == b.name);
    REQUIRE(a.width == b.width);
    REQUIRE(a.height == b.height);
    REQUIRE(a.fx == Approx(b.fx).margin(1e-9));
    REQUIRE(a.fy == Approx(b.fy).margin(1e-9));
    REQUIRE(a.cx == Approx(b.cx).margin(1e-9));
    REQUIRE(a.cy == Approx(b.cy).margin(1e-9));
    require_near(a.R, b.R);
    require_near(a.t, b.t);
    if (same_model) {
        REQUIRE(a.model == b.model);
        REQUIRE(a.distortion.size() == b.distortion.size());
        for (size_t k = 0; k < a.distortion.size(); ++k) REQUIRE(a.distortion[k] == Approx(b.distortion[k]).margin(1e-12));
    }
}

// Cameras on a ring looking at the origin, some rolled, with varied intrinsics.
std::vector<Camera> sample_cameras() {
    std::vector<Camera> cams;
    for (int i = 0; i < 6; ++i) {
        Camera c;
        c.name = "view_" + std::to_string(i);
        c.width = 640 + 16 * i;
        c.height = 480 - 8 * i;
        c.fx = 500.25 + 10 * i;
        c.fy = 501.5 + 7 * i;
        c.cx = c.width / 2.0 + 0.25 * i;
        c.cy = c.height / 2.0 - 0.5 * i;
        const double a = 1.1 * i + 0.3;
        const glm::dquat q = glm::angleAxis(a, glm::normalize(glm::dvec3(0.2 * i - 0.5, 1.0, 0.3)));
        c.R = glm::mat3_cast(q);
        c.t = glm::dvec3(0.1 * i, -0.2, 4.0 + i);
        cams.push_back(c);
    }
    // The two branches of the quaternion conversion with a negative trace.
    cams[4].R = glm::mat3_cast(glm::angleAxis(3.0, glm::normalize(glm::dvec3(1, 0.1, 0))));
    cams[5].R = glm::mat3_cast(glm::angleAxis(3.1, glm::normalize(glm::dvec3(0, 0.2, 1))));
    return cams;
}

Camera forward_camera() {
    // World position (0,0,-5), looking along +z, y down: R = I, t = (0,0,5).
    Camera c;
    c.name = "frame_001";
    c.width = 64;
    c.height = 48;
    c.fx = 50;
    c.fy = 52;
    c.cx = 32;
    c.cy = 24;
    c.t = {0, 0, 5};
    return c;
}

void require_forward_camera(const std::vector<Camera>& cams) {
    REQUIRE(cams.size() == 1);
    const Camera& c = cams[0];
    REQUIRE(c.name == "frame_001");
    require_near(c.R, glm::dmat3(1.0));
    require_near(c.t, {0, 0, 5});
    require_near(c.position(), {0, 0, -5});
    require_near(c.forward(), {0, 0, 1});
    require_near(c.up(), {0, -1, 0});
    // (1, -0.5, 5) is 10 in front of the camera: u = fx*0.1 + cx, v = fy*-0.05 + cy.
    const glm::dvec2 uv = project(c, {1, -0.5, 5});
    REQUIRE(uv.x == Approx(50 * 0.1 + 32));
    REQUIRE(uv.y == Approx(c.fy * -0.05 + 24));
}

std::string cameras_bin_one(int32_t model_id, uint64_t w, uint64_t h, const std::vector<double>& params) {
    std::string b;
    append<uint64_t>(b, 1);
    append<int32_t>(b, 1);
    append<int32_t>(b, model_id);
    append<uint64_t>(b, w);
    append<uint64_t>(b, h);
    for (double p : params) append<double>(b, p);
    return b;
}

// nerfstudio's transform_matrix (camera-to-world, OpenGL axes) for an OpenCV camera; written
// here independently of the reader.
nlohmann::json transform_matrix_gl(const Camera& c) {
    const glm::dmat3 c2w = glm::transpose(c.R);  // columns: camera x, y, z in world (OpenCV)
    const glm::dvec3 centre = c.position();
    nlohmann::json m = nlohmann::json::array();
    for (int r = 0; r < 3; ++r) m.push_back({c2w[0][r], -c2w[1][r], -c2w[2][r], centre[r]});
    m.push_back({0, 0, 0, 1});
    return m;
}

}  // namespace

TEST_CASE("Camera: world_to_camera, project, has_distortion, resized", "[cameras]") {
    Camera c = sample_cameras()[2];
    const glm::dvec3 p(0.3, -1.2, 2.0);
    const glm::dvec4 q = c.world_to_camera() * glm::dvec4(p, 1.0);
    require_near(glm::dvec3(q), c.R * p + c.t);
    REQUIRE(q.w == 1.0);
    REQUIRE(q.z > 0);
    const auto uv = c.project(p);
    REQUIRE(uv);
    REQUIRE(uv->x == Approx(project(c, p).x));
    REQUIRE(uv->y == Approx(project(c, p).y));
    // The point mirrored through the camera centre lies behind it: no pixel.
    REQUIRE_FALSE(c.project(2.0 * c.position() - p));
    REQUIRE_FALSE(c.project(c.position()));

    REQUIRE_FALSE(c.has_distortion());
    c.distortion = {0, 0, 0, 0};
    REQUIRE_FALSE(c.has_distortion());
    c.distortion = {0, 0.01, 0, 0};
    REQUIRE(c.has_distortion());

    const Camera half = c.resized(c.width / 2, c.height / 2);
    REQUIRE(half.width == c.width / 2);
    REQUIRE(half.fx == Approx(c.fx / 2));
    REQUIRE(half.cy == Approx(c.cy / 2));
    // A point projects to the same relative place in both images.
    const glm::dvec2 a = project(c, p), b = project(half, p);
    REQUIRE(b.x == Approx(a.x / 2));
    REQUIRE(b.y == Approx(a.y / 2));
    REQUIRE_THROWS_AS(c.resized(0, 10), std::invalid_argument);
}

TEST_CASE("COLMAP text: hand-checked camera at (0,0,-5) looking along +z", "[cameras]") {
    const fs::path dir = fresh_scratch("cams_colmap_txt_hand");
    write_text(dir / "cameras.txt", "# comment\n1 PINHOLE 64 48 50 52 32 24\n");
    write_text(dir / "images.txt", "# IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME\n"
                                   "1 1 0 0 0 0 0 5 1 images/frame_001.png\n"
                                   "10.5 20.5 -1 30 40 7\n");
    require_forward_camera(pg::data::read_colmap(dir));
}

TEST_CASE("COLMAP binary: hand-checked camera at (0,0,-5) looking along +z", "[cameras]") {
    const fs::path dir = fresh_scratch("cams_colmap_bin_hand");
    write_bytes(dir / "cameras.bin", cameras_bin_one(1, 64, 48, {50, 52, 32, 24}));
    std::string im;
    append<uint64_t>(im, 1);
    append<int32_t>(im, 1);
    for (double v : {1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 5.0}) append<double>(im, v);
    append<int32_t>(im, 1);
    im += std::string("frame_001.png") + '\0';
    append<uint64_t>(im, 2);  // two 2D points, skipped
    for (int k = 0; k < 2; ++k) {
        append<double>(im, 1.5);
        append<double>(im, 2.5);
        append<int64_t>(im, -1);
    }
    write_bytes(dir / "images.bin", im);
    require_forward_camera(pg::data::read_colmap(dir));
}

TEST_CASE("INRIA cameras.json: hand-checked camera at (0,0,-5) looking along +z", "[cameras]") {
    const fs::path file = fresh_scratch("cams_inria_hand") / "cameras.json";
    write_text(file, R"([{"id": 0, "img_name": "frame_001", "width": 64, "height": 48,
        "position": [0.0, 0.0, -5.0], "rotation": [[1,0,0],[0,1,0],[0,0,1]], "fy": 52.0, "fx": 50.0}])");
    const auto cams = pg::data::read_inria_cameras_json(file);
    require_forward_camera(cams);
    REQUIRE(cams[0].cx == 32);  // INRIA: principal point at the centre
    REQUIRE(cams[0].cy == 24);
}

TEST_CASE("nerfstudio transforms.json: hand-checked camera at (0,0,-5) looking along +z", "[cameras]") {
    const fs::path file = fresh_scratch("cams_ns_hand") / "transforms.json";
    write_text(file, R"({"fl_x": 50, "fl_y": 52, "cx": 32, "cy": 24, "w": 64, "h": 48,
        "frames": [{"file_path": "images/frame_001.png",
                    "transform_matrix": [[1,0,0,0],[0,-1,0,0],[0,0,-1,-5],[0,0,0,1]]}]})");
    require_forward_camera(pg::data::read_transforms_json(file));
}

TEST_CASE("INRIA cameras.json: rotation rows are camera-to-world", "[cameras]") {
    // A camera at (5,0,0) looking at the origin (along world -x) with image-down = world -z.
    // Camera axes in world: x = (0,1,0), y = (0,0,-1), z = (-1,0,0); C2W's columns.
    const fs::path file = fresh_scratch("cams_inria_turned") / "cameras.json";
    write_text(file, R"([{"id": 0, "img_name": "side", "width": 100, "height": 80,
        "position": [5, 0, 0], "rotation": [[0,0,-1],[1,0,0],[0,-1,0]], "fy": 40, "fx": 40}])");
    const Camera c = pg::data::read_inria_cameras_json(file).at(0);
    require_near(c.forward(), {-1, 0, 0});
    require_near(c.up(), {0, 0, 1});
    const glm::dvec2 origin = project(c, {0, 0, 0});
    REQUIRE(origin.x == Approx(50));
    REQUIRE(origin.y == Approx(40));
    // World +y is to the camera's right, world +z is up.
    REQUIRE(project(c, {0, 1, 0}).x == Approx(50 + 40 * 1.0 / 5));
    REQUIRE(project(c, {0, 0, 1}).y == Approx(40 - 40 * 1.0 / 5));
}

TEST_CASE("nerfstudio transforms.json: OpenGL axes and NeRF-synthetic camera_angle_x", "[cameras]") {
    // A camera at (5,0,0) looking at the origin with GL up = world +z: GL axes in world
    // x = (0,1,0), y = (0,0,1), z (back) = (1,0,0).
    const fs::path file = fresh_scratch("cams_ns_synthetic") / "transforms_train.json";
    const double angle = 0.6911112070083618;
    write_text(file, R"({"camera_angle_x": 0.6911112070083618,
        "frames": [{"file_path": "./train/r_0", "w": 800, "h": 800,
                    "transform_matrix": [[0,0,1,5],[1,0,0,0],[0,1,0,0],[0,0,0,1]]}]})");
    const Camera c = pg::data::read_transforms_json(file).at(0);
    REQUIRE(c.name == "r_0");
    const double f = 0.5 * 800 / std::tan(angle / 2);
    REQUIRE(c.fx == Approx(f));
    REQUIRE(c.fy == Approx(f));
    REQUIRE(c.cx == 400);
    require_near(c.position(), {5, 0, 0});
    require_near(c.forward(), {-1, 0, 0});
    require_near(c.up(), {0, 0, 1});
    REQUIRE(project(c, {0, 0, 0}).x == Approx(400));
    REQUIRE(project(c, {0, 1, 0}).x == Approx(400 + f / 5));  // right
    REQUIRE(project(c, {0, 0, 1}).y == Approx(400 - f / 5));  // up is towards the top row
}

TEST_CASE("nerfstudio transforms.json: per-frame intrinsics override the top level", "[cameras]") {
    const fs::path file = fresh_scratch("cams_ns_override") / "transforms.json";
    write_text(file, R"({"fl_x": 50, "w": 64, "h": 48, "k1": 0.0,
        "frames": [
          {"file_path": "b.jpg", "transform_matrix": [[1,0,0,0],[0,-1,0,0],[0,0,-1,-5],[0,0,0,1]]},
          {"file_path": "a.jpg", "fl_x": 70, "fl_y": 71, "cx": 30, "cy": 20, "w": 60, "h": 40,
           "transform_matrix": [[1,0,0,0],[0,-1,0,0],[0,0,-1,-5],[0,0,0,1]]}]})");
    const auto cams = pg::data::read_transforms_json(file);
    REQUIRE(cams.size() == 2);
    REQUIRE(cams[0].name == "a");  // sorted by name
    REQUIRE(cams[0].fx == 70);
    REQUIRE(cams[0].fy == 71);
    REQUIRE(cams[0].cx == 30);
    REQUIRE(cams[0].width == 60);
    REQUIRE(cams[1].name == "b");
    REQUIRE(cams[1].fx == 50);
    REQUIRE(cams[1].fy == 50);  // fl_y defaults to fl_x
    REQUIRE(cams[1].cx == 32);  // cx defaults to the centre
    REQUIRE(cams[1].cy == 24);
    REQUIRE_FALSE(cams[1].has_distortion());
}

TEST_CASE("COLMAP round trip, text and binary, every writable model", "[cameras]") {
    auto cams = sample_cameras();
    cams[1].model = "SIMPLE_PINHOLE";
    cams[1].fy = cams[1].fx;
    cams[2].model = "SIMPLE_RADIAL";
    cams[2].fy = cams[2].fx;
    cams[2].distortion = {-0.05};
    cams[3].model = "RADIAL";
    cams[3].fy = cams[3].fx;
    cams[3].distortion = {-0.05, 0.01};
    cams[4].model = "OPENCV";
    cams[4].distortion = {-0.05, 0.01, 0.001, -0.002};
    const fs::path root = fresh_scratch("cams_colmap_roundtrip");
    CerrCapture quiet;
    for (const bool binary : {false, true}) {
        INFO((binary ? "binary" : "text"));
        const fs::path dir = root / (binary ? "bin" : "txt");
        binary ? pg::data::write_colmap_binary(cams, dir) : pg::data::write_colmap_text(cams, dir);
        const char* ext = binary ? ".bin" : ".txt";
        for (const char* f : {"cameras", "images", "points3D"}) REQUIRE(fs::is_regular_file(dir / (f + std::string(ext))));
        const auto back = pg::data::read_colmap(dir);
        REQUIRE(back.size() == cams.size());
        for (size_t i = 0; i < cams.size(); ++i) require_same(back[i], cams[i]);
    }
}

TEST_CASE("COLMAP writer: radial distortion on two focal lengths becomes OPENCV", "[cameras]") {
    auto cams = sample_cameras();
    cams.resize(1);
    cams[0].model = "SIMPLE_RADIAL";
    cams[0].distortion = {0.02};  // fx != fy: SIMPLE_RADIAL cannot hold it
    const fs::path dir = fresh_scratch("cams_colmap_opencv");
    pg::data::write_colmap_text(cams, dir);
    CerrCapture quiet;
    const Camera back = pg::data::read_colmap(dir).at(0);
    require_same(back, cams[0], false);
    REQUIRE(back.model == "OPENCV");
    REQUIRE(back.distortion == std::vector<double>{0.02, 0, 0, 0});
}

TEST_CASE("INRIA cameras.json round trip", "[cameras]") {
    auto cams = sample_cameras();
    cams[0].cx = cams[0].width / 2.0;  // centred: the standard layout
    cams[0].cy = cams[0].height / 2.0;
    const fs::path file = fresh_scratch("cams_inria_roundtrip") / "cameras.json";
    pg::data::write_inria_cameras_json(cams, file);
    const auto doc = nlohmann::json::parse(std::ifstream(file));
    REQUIRE(doc.size() == cams.size());
    REQUIRE_FALSE(doc[0].contains("cx"));
    for (const char* key : {"id", "img_name", "width", "height", "position", "rotation", "fy", "fx"})
        REQUIRE(doc[1].contains(key));
    REQUIRE(doc[1].contains("cx"));  // off-centre principal point kept as an extra key
    const auto back = pg::data::read_inria_cameras_json(file);
    REQUIRE(back.size() == cams.size());
    for (size_t i = 0; i < cams.size(); ++i) require_same(back[i], cams[i]);
    // position is the camera centre and rotation's rows are C2W's rows.
    const glm::dmat3 c2w = glm::transpose(cams[3].R);
    for (int r = 0; r < 3; ++r) {
        REQUIRE(doc[3]["position"][size_t(r)].get<double>() == Approx(cams[3].position()[r]));
        for (int c = 0; c < 3; ++c) REQUIRE(doc[3]["rotation"][size_t(r)][size_t(c)].get<double>() == Approx(c2w[c][r]).margin(1e-12));
    }
}

TEST_CASE("nerfstudio transforms.json round trip", "[cameras]") {
    const auto cams = sample_cameras();
    nlohmann::json doc;
    doc["frames"] = nlohmann::json::array();
    for (const Camera& c : cams)
        doc["frames"].push_back({{"file_path", "images/" + c.name + ".png"}, {"fl_x", c.fx}, {"fl_y", c.fy},
                                 {"cx", c.cx}, {"cy", c.cy}, {"w", c.width}, {"h", c.height},
                                 {"transform_matrix", transform_matrix_gl(c)}});
    const fs::path file = fresh_scratch("cams_ns_roundtrip") / "transforms.json";
    write_text(file, doc.dump(1));
    const auto back = pg::data::read_transforms_json(file);
    REQUIRE(back.size() == cams.size());
    for (size_t i = 0; i < cams.size(); ++i) require_same(back[i], cams[i]);
}

TEST_CASE("COLMAP: each supported camera model is parsed", "[cameras]") {
    const fs::path dir = fresh_scratch("cams_colmap_models");
    write_text(dir / "cameras.txt", "1 SIMPLE_PINHOLE 100 80 90 50 40\n"
                                    "2 PINHOLE 100 80 90 91 51 41\n"
                                    "3 SIMPLE_RADIAL 100 80 92 52 42 0.1\n"
                                    "4 RADIAL 100 80 93 53 43 0.1 0.2\n"
                                    "5 OPENCV 100 80 94 95 54 44 0.1 0.2 0.3 0.4\n");
    std::string images;
    for (int i = 1; i <= 5; ++i)
        images += std::to_string(i) + " 1 0 0 0 0 0 1 " + std::to_string(i) + " im" + std::to_string(i) + ".jpg\n\n";
    write_text(dir / "images.txt", images);
    CerrCapture quiet;
    const auto c = pg::data::read_colmap(dir);
    REQUIRE(c.size() == 5);
    auto check = [](const Camera& cam, const char* model, double fx, double fy, double cx, double cy,
                    std::vector<double> dist) {
        INFO(model);
        REQUIRE(cam.model == model);
        REQUIRE(cam.width == 100);
        REQUIRE(cam.height == 80);
        REQUIRE(cam.fx == fx);
        REQUIRE(cam.fy == fy);
        REQUIRE(cam.cx == cx);
        REQUIRE(cam.cy == cy);
        REQUIRE(cam.distortion == dist);
    };
    check(c[0], "SIMPLE_PINHOLE", 90, 90, 50, 40, {});
    check(c[1], "PINHOLE", 90, 91, 51, 41, {});
    check(c[2], "SIMPLE_RADIAL", 92, 92, 52, 42, {0.1});
    check(c[3], "RADIAL", 93, 93, 53, 43, {0.1, 0.2});
    check(c[4], "OPENCV", 94, 95, 54, 44, {0.1, 0.2, 0.3, 0.4});
}

TEST_CASE("Lens distortion is reported once per file", "[cameras]") {
    const fs::path dir = fresh_scratch("cams_distortion");
    write_text(dir / "cameras.txt", "1 OPENCV 100 80 94 95 54 44 0.1 0 0 0\n2 OPENCV 100 80 94 95 54 44 0 0 0 0\n");
    write_text(dir / "images.txt", "1 1 0 0 0 0 0 1 1 a.png\n\n2 1 0 0 0 0 0 1 1 b.png\n\n3 1 0 0 0 0 0 1 2 c.png\n\n");
    {
        CerrCapture err;
        const auto cams = pg::data::read_colmap(dir);
        REQUIRE(cams.size() == 3);
        REQUIRE(cams[0].has_distortion());
        REQUIRE_FALSE(cams[2].has_distortion());
        const std::string text = err.text.str();
        REQUIRE(text.find("lens distortion ignored by the pinhole renderer") != std::string::npos);
        REQUIRE(text.find("2 of 3") != std::string::npos);
        REQUIRE(text.find("images.txt") != std::string::npos);
        REQUIRE(std::count(text.begin(), text.end(), '\n') == 1);
    }
    const fs::path ns = dir / "transforms.json";
    write_text(ns, R"({"fl_x": 50, "w": 64, "h": 48, "k1": -0.1, "p2": 0.01,
        "frames": [{"file_path": "a.png", "transform_matrix": [[1,0,0,0],[0,-1,0,0],[0,0,-1,-5],[0,0,0,1]]}]})");
    {
        CerrCapture err;
        const Camera c = pg::data::read_transforms_json(ns).at(0);
        REQUIRE(c.model == "OPENCV");
        REQUIRE(c.distortion == std::vector<double>{-0.1, 0, 0, 0.01});
        REQUIRE(err.text.str().find("lens distortion ignored") != std::string::npos);
    }
    {
        CerrCapture err;  // no distortion: no warning
        write_text(dir / "cameras.txt", "1 OPENCV 100 80 94 95 54 44 0 0 0 0\n2 PINHOLE 100 80 94 95 54 44\n");
        pg::data::read_colmap(dir);
        REQUIRE(err.text.str().empty());
    }
}

TEST_CASE("load_cameras dispatches on folders, file names and JSON content", "[cameras]") {
    const fs::path root = fresh_scratch("cams_dispatch");
    const std::vector<Camera> cams = {forward_camera()};
    pg::data::write_colmap_binary(cams, root / "scene" / "sparse" / "0");
    pg::data::write_colmap_text(cams, root / "model_txt");
    pg::data::write_inria_cameras_json(cams, root / "output" / "cameras.json");
    write_text(root / "ns" / "transforms.json", R"({"fl_x": 50, "fl_y": 52, "cx": 32, "cy": 24, "w": 64, "h": 48,
        "frames": [{"file_path": "images/frame_001.png",
                    "transform_matrix": [[1,0,0,0],[0,-1,0,0],[0,0,-1,-5],[0,0,0,1]]}]})");
    fs::copy_file(root / "ns" / "transforms.json", root / "renamed_nerfstudio.json");
    fs::copy_file(root / "output" / "cameras.json", root / "renamed_inria.JSON");

    for (const fs::path& p : {root / "scene", root / "scene" / "sparse" / "0", root / "scene" / "sparse" / "0" / "images.bin",
                              root / "scene" / "sparse" / "0" / "cameras.bin", root / "model_txt",
                              root / "model_txt" / "images.txt", root / "model_txt" / "cameras.txt", root / "output",
                              root / "output" / "cameras.json", root / "ns", root / "ns" / "transforms.json",
                              root / "renamed_nerfstudio.json", root / "renamed_inria.JSON"}) {
        INFO(p.string());
        require_forward_camera(pg::data::load_cameras(p));
    }
}

TEST_CASE("load_cameras names a missing path", "[cameras]") {
    const fs::path missing = fresh_scratch("cams_missing") / "no_such_cameras.json";
    try {
        pg::data::load_cameras(missing);
        FAIL("no error");
    } catch (const pg::data::InputError& e) {
        REQUIRE(std::string(e.what()).find("no_such_cameras.json") != std::string::npos);
    }
    REQUIRE_THROWS_AS(pg::data::read_colmap(missing.parent_path()), pg::data::InputError);
    REQUIRE_THROWS_AS(pg::data::read_inria_cameras_json(missing), pg::data::InputError);
    REQUIRE_THROWS_AS(pg::data::read_transforms_json(missing), pg::data::InputError);
}

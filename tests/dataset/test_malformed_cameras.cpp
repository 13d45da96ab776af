// Broken camera input ends in an InputError naming the file, never a crash: the committed
// corpus (tools/make_malformed_cameras.py), every truncation of good files, byte flips, and
// writers refusing bad cameras without leaving files behind.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <iostream>
#include <sstream>

#include <catch2/catch.hpp>

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

struct CerrCapture {
    std::ostringstream text;
    std::streambuf* old = std::cerr.rdbuf(text.rdbuf());
    ~CerrCapture() { std::cerr.rdbuf(old); }
};

// The InputError's message, or "" when the call succeeded; any other exception escapes and
// fails the test.
template <class F>
std::string input_error(F&& f) {
    try {
        f();
    } catch (const pg::data::InputError& e) {
        return e.what();
    }
    return "";
}

std::string read_bytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

void write_bytes(const fs::path& p, const std::string& bytes) { std::ofstream(p, std::ios::binary) << bytes; }

Camera good_camera(const std::string& name) {
    Camera c;
    c.name = name;
    c.width = 64;
    c.height = 48;
    c.fx = 50;
    c.fy = 51;
    c.cx = 31;
    c.cy = 23;
    c.R = glm::dmat3(0, 0, -1, 1, 0, 0, 0, -1, 0);  // columns; a proper rotation
    c.t = {0.5, -0.25, 5};
    return c;
}

// Every prefix of `file` shorter than the whole must fail with an InputError naming it (a
// text file cut after a whole record may still load), and flipping any byte must either
// still load or fail the same way.
void torture(const fs::path& file, bool prefixes_fail, const std::function<std::vector<Camera>()>& load) {
    const std::string good = read_bytes(file);
    CerrCapture quiet;
    for (size_t n = 0; n < good.size(); ++n) {
        write_bytes(file, good.substr(0, n));
        const std::string msg = input_error(load);
        INFO(file.filename().string() << " truncated to " << n << " of " << good.size() << " bytes");
        if (prefixes_fail) REQUIRE_FALSE(msg.empty());
        if (!msg.empty()) REQUIRE(msg.find(file.filename().string()) != std::string::npos);
    }
    for (size_t i = 0; i < good.size(); ++i)
        for (const unsigned char mask : {0x80u, 0x01u, 0xffu}) {
            std::string bad = good;
            bad[i] = char(static_cast<unsigned char>(bad[i]) ^ mask);
            write_bytes(file, bad);
            const std::string msg = input_error(load);
            INFO(file.filename().string() << " byte " << i << " xor " << int(mask));
            if (!msg.empty()) REQUIRE(msg.find(file.filename().string()) != std::string::npos);
        }
    write_bytes(file, good);
    REQUIRE(load().size() == 2);
}

}  // namespace

TEST_CASE("Malformed camera corpus: every case is an InputError naming the file", "[cameras][malformed]") {
    const fs::path dir = pg::test::fixtures() / "malformed" / "cameras";
    REQUIRE(fs::is_directory(dir));
    std::vector<fs::path> cases;
    for (const auto& entry : fs::directory_iterator(dir)) cases.push_back(entry.path());
    std::sort(cases.begin(), cases.end());
    REQUIRE(cases.size() >= 60);
    CerrCapture quiet;
    for (const fs::path& c : cases) {
        const std::string msg = input_error([&] { pg::data::load_cameras(c); });
        INFO("case " << c.filename().string() << ": " << msg);
        REQUIRE_FALSE(msg.empty());
        REQUIRE(msg.find(c.filename().string()) != std::string::npos);
    }
}

TEST_CASE("Malformed cameras: specific reasons are named", "[cameras][malformed]") {
    const fs::path dir = pg::test::fixtures() / "malformed" / "cameras";
    CerrCapture quiet;
    auto reason = [&](const char* name) { return input_error([&] { pg::data::load_cameras(dir / name); }); };
    CHECK_THAT(reason("bin_unsupported_full_opencv"), Catch::Contains("FULL_OPENCV"));
    CHECK_THAT(reason("txt_unsupported_fisheye"), Catch::Contains("OPENCV_FISHEYE"));
    CHECK_THAT(reason("bin_unknown_camera_id"), Catch::Contains("camera id 7"));
    CHECK_THAT(reason("bin_huge_image_count"), Catch::Contains("bytes follow"));
    CHECK_THAT(reason("bin_truncated_cameras"), Catch::Contains("truncated"));
    CHECK_THAT(reason("bin_zero_quaternion"), Catch::Contains("zero length"));
    CHECK_THAT(reason("bin_nan_quaternion"), Catch::Contains("not finite"));
    CHECK_THAT(reason("bin_no_images"), Catch::Contains("no cameras"));
    CHECK_THAT(reason("bin_truncated_images_name"), Catch::Contains("image name"));
    CHECK_THAT(reason("bin_duplicate_names"), Catch::Contains("frame_001"));
    CHECK_THAT(reason("txt_bad_number"), Catch::Contains("line 3"));
    CHECK_THAT(reason("inria_truncated.json"), Catch::Contains("invalid JSON"));
    CHECK_THAT(reason("inria_missing_fx.json"), Catch::Contains("'fx'"));
    CHECK_THAT(reason("inria_rotation_scaled.json"), Catch::Contains("orthonormal"));
    CHECK_THAT(reason("ns_no_focal.json"), Catch::Contains("camera_angle_x"));
    CHECK_THAT(reason("ns_angle_without_size.json"), Catch::Contains("'w'"));
    CHECK_THAT(reason("ns_fisheye.json"), Catch::Contains("OPENCV_FISHEYE"));
}

TEST_CASE("Malformed cameras: truncated and corrupted COLMAP binary files", "[cameras][malformed]") {
    const fs::path dir = fresh_scratch("cams_torture_bin");
    auto cams = std::vector<Camera>{good_camera("a"), good_camera("b")};
    cams[1].model = "OPENCV";
    cams[1].distortion = {0.1, 0, 0, 0};
    pg::data::write_colmap_binary(cams, dir);
    torture(dir / "cameras.bin", true, [&] { return pg::data::read_colmap(dir); });
    torture(dir / "images.bin", true, [&] { return pg::data::read_colmap(dir); });
}

TEST_CASE("Malformed cameras: truncated and corrupted COLMAP text files", "[cameras][malformed]") {
    const fs::path dir = fresh_scratch("cams_torture_txt");
    pg::data::write_colmap_text({good_camera("a"), good_camera("b")}, dir);
    torture(dir / "cameras.txt", false, [&] { return pg::data::read_colmap(dir); });
    torture(dir / "images.txt", false, [&] { return pg::data::read_colmap(dir); });
}

TEST_CASE("Malformed cameras: truncated and corrupted JSON files", "[cameras][malformed]") {
    const fs::path dir = fresh_scratch("cams_torture_json");
    pg::data::write_inria_cameras_json({good_camera("a"), good_camera("b")}, dir / "cameras.json");
    torture(dir / "cameras.json", true, [&] { return pg::data::load_cameras(dir / "cameras.json"); });
    write_bytes(dir / "transforms.json", R"({"fl_x": 50, "w": 64, "h": 48, "frames": [
        {"file_path": "a.png", "transform_matrix": [[1,0,0,0],[0,-1,0,0],[0,0,-1,-5],[0,0,0,1]]},
        {"file_path": "b.png", "transform_matrix": [[1,0,0,1],[0,-1,0,0],[0,0,-1,-5],[0,0,0,1]]}]})");
    torture(dir / "transforms.json", true, [&] { return pg::data::load_cameras(dir / "transforms.json"); });
}

TEST_CASE("Camera writers refuse bad cameras and leave no file behind", "[cameras][malformed]") {
    const fs::path dir = fresh_scratch("cams_bad_writes");
    Camera bad = good_camera("x");
    bad.fx = std::nan("");
    REQUIRE_THROWS_AS(pg::data::write_colmap_binary({bad}, dir / "bin"), pg::data::InputError);
    REQUIRE_THROWS_AS(pg::data::write_colmap_text({bad}, dir / "txt"), pg::data::InputError);
    REQUIRE_THROWS_AS(pg::data::write_inria_cameras_json({bad}, dir / "cameras.json"), pg::data::InputError);
    REQUIRE(fs::is_empty(dir));

    Camera fisheye = good_camera("y");
    fisheye.model = "OPENCV_FISHEYE";
    fisheye.distortion = {0.1, 0, 0, 0};
    const std::string msg = input_error([&] { pg::data::write_colmap_text({fisheye}, dir / "txt"); });
    REQUIRE_THAT(msg, Catch::Contains("OPENCV_FISHEYE"));

    Camera newline = good_camera("two\nlines");
    REQUIRE_THROWS_AS(pg::data::write_colmap_text({newline}, dir / "txt"), pg::data::InputError);
    REQUIRE(fs::is_empty(dir));

    // The model folder cannot be created where a file stands.
    write_bytes(dir / "a_file", "x");
    REQUIRE_THROWS_AS(pg::data::write_colmap_binary({good_camera("z")}, dir / "a_file" / "sparse"),
                      pg::data::InputError);
}

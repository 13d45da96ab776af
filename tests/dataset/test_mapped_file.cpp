// MappedFile: the bytes as on disk, still readable after their pages are released; missing and
// empty files behave as read_file does.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include "dataset/error.h"
#include "dataset/formats/scene_io.h"
#include "dataset/mapped_file.h"

namespace fs = std::filesystem;

TEST_CASE("mapped file: bytes as written, readable again after release") {
    const fs::path path = fs::temp_directory_path() / "pg_mapped_file.bin";
    std::vector<char> bytes(3 * 65536 + 123);
    for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = char((i * 2654435761u) >> 13);
    std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
    {
        pg::data::MappedFile f(path);
        REQUIRE(f.size() == bytes.size());
        CHECK(std::equal(bytes.begin(), bytes.end(), f.data()));
        f.release(2 * 65536 + 7);
        f.release(100);  // behind what was released: nothing
        CHECK(std::equal(bytes.begin(), bytes.end(), f.data()));
        f.release(f.size() + 4096);
        CHECK(std::equal(bytes.begin(), bytes.end(), f.data()));
    }
    fs::remove(path);
}

TEST_CASE("mapped file: an empty file has no bytes, a missing one is an InputError naming it") {
    const fs::path path = fs::temp_directory_path() / "pg_mapped_empty.bin";
    std::ofstream(path, std::ios::binary).close();
    pg::data::MappedFile f(path);
    CHECK(f.size() == 0);
    fs::remove(path);
    try {
        pg::data::MappedFile missing(path);
        FAIL("no error");
    } catch (const pg::data::InputError& e) {
        CHECK(std::string(e.what()).find(path.string()) != std::string::npos);
        CHECK(std::string(e.what()).find("no such file") != std::string::npos);
    }
}

TEST_CASE("a PLY past the reader's release interval loads the same as its copy written back") {
    // 200k Gaussians: the reader gives pages back three times while parsing.
    pg::data::GaussianCloud c;
    c.resize(200000);
    for (size_t i = 0; i < c.size(); ++i) {
        c.mean[i] = glm::vec3(float(i), float(i % 7), -float(i % 13));
        c.opacity_logit[i] = float(i % 100) / 10.0f - 5.0f;
        c.log_scale[i] = glm::vec3(-float(i % 5));
    }
    const fs::path path = fs::temp_directory_path() / "pg_mapped_big.ply";
    pg::data::write_ply(c, path);
    const auto back = pg::data::load_scene(path);
    fs::remove(path);
    REQUIRE(back.size() == c.size());
    CHECK(back.mean == c.mean);
    CHECK(back.opacity_logit == c.opacity_logit);
    CHECK(back.log_scale == c.log_scale);
}

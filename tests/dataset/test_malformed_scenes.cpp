// Every file of tests/fixtures/malformed/scenes (written by tools/make_malformed_scenes.py)
// must end in an InputError that names the file and gives the expected reason.
#include <catch2/catch.hpp>

#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "dataset/error.h"
#include "dataset/formats/scene_io.h"
#include "tests/test_paths.h"

namespace fs = std::filesystem;
using pg::data::InputError;

namespace {

fs::path corpus_dir() { return pg::test::fixtures() / "malformed" / "scenes"; }

// file name -> text its error message must contain
std::map<std::string, std::string> expected_reasons() {
    std::map<std::string, std::string> out;
    std::ifstream in(pg::test::fixtures() / "malformed" / "scenes_expected.tsv");
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        auto tab = line.find('\t');
        if (tab != std::string::npos) out[line.substr(0, tab)] = line.substr(tab + 1);
    }
    return out;
}

std::string load_error(const fs::path& p) {
    try {
        pg::data::load_scene(p);
    } catch (const InputError& e) {
        return e.what();
    }
    return {};
}

}  // namespace

TEST_CASE("malformed scenes: every corpus file throws InputError naming the file") {
    REQUIRE(fs::is_directory(corpus_dir()));
    size_t files = 0;
    for (const auto& entry : fs::directory_iterator(corpus_dir())) {
        if (!entry.is_regular_file()) continue;
        ++files;
        const fs::path p = entry.path();
        INFO("file: " << p.filename().string());
        REQUIRE_THROWS_AS(pg::data::load_scene(p), InputError);
        const std::string message = load_error(p);
        INFO("message: " << message);
        CHECK(message.find(p.filename().string()) != std::string::npos);
    }
    CHECK(files >= 60);
}

TEST_CASE("malformed scenes: each error gives the specific reason") {
    const auto expected = expected_reasons();
    REQUIRE(expected.size() >= 60);
    for (const auto& [name, reason] : expected) {
        const fs::path p = corpus_dir() / name;
        INFO("file: " << name << "\nexpected reason: " << reason);
        REQUIRE(fs::exists(p));
        const std::string message = load_error(p);
        INFO("message: " << message);
        CHECK(message.find(reason) != std::string::npos);
    }
}

TEST_CASE("malformed scenes: the format readers reject each other's files") {
    const fs::path dir = corpus_dir();
    // Called directly, each reader still fails cleanly on a file of another kind.
    CHECK_THROWS_AS(pg::data::read_ply(dir / "splat_size_33.splat"), InputError);
    CHECK_THROWS_AS(pg::data::read_ply(dir / "spz_bad_magic.spz"), InputError);
    CHECK_THROWS_AS(pg::data::read_splat(dir / "missing_x.ply"), InputError);
    CHECK_THROWS_AS(pg::data::read_spz(dir / "missing_x.ply"), InputError);
    CHECK_THROWS_AS(pg::data::read_spz(dir / "empty.ply"), InputError);
    CHECK_THROWS_AS(pg::data::read_splat(dir / "empty.ply"), InputError);
    CHECK_THROWS_AS(pg::data::load_scene(dir / "no_such_file.ply"), InputError);
    CHECK_THROWS_AS(pg::data::load_scene(dir), InputError);
}

TEST_CASE("malformed scenes: every truncation of a valid PLY fails cleanly") {
    // A small valid binary PLY cut at every byte: each prefix either loads (when the cut
    // falls after the data) or throws InputError, never anything else.
    std::ostringstream ply;
    ply << "ply\nformat binary_little_endian 1.0\nelement vertex 3\n";
    for (const char* n : {"x", "y", "z", "f_dc_0", "f_dc_1", "f_dc_2", "opacity", "scale_0", "scale_1", "scale_2",
                          "rot_0", "rot_1", "rot_2", "rot_3"})
        ply << "property float " << n << "\n";
    ply << "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    std::string bytes = ply.str();
    for (int i = 0; i < 3; ++i) {
        float row[14] = {float(i), 1, 2, 0.1f, 0.2f, 0.3f, 0.5f, -2, -2, -2, 1, 0, 0, 0};
        bytes.append(reinterpret_cast<const char*>(row), sizeof row);
    }
    bytes.push_back(3);
    for (int32_t v : {0, 1, 2}) bytes.append(reinterpret_cast<const char*>(&v), 4);

    const fs::path p = pg::test::scratch("malformed_scenes") / "cut.ply";
    for (size_t cut = 0; cut < bytes.size(); ++cut) {
        {
            std::ofstream out(p, std::ios::binary | std::ios::trunc);
            out.write(bytes.data(), static_cast<std::streamsize>(cut));
        }
        INFO("cut at " << cut);
        CHECK_THROWS_AS(pg::data::read_ply(p), InputError);
    }
    {
        std::ofstream out(p, std::ios::binary | std::ios::trunc);
        out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    }
    CHECK(pg::data::read_ply(p).size() == 3);
}

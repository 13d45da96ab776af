// `pointgauss eval` end to end: a real process on a tiny suite written here.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sys/wait.h>

#include <nlohmann/json.hpp>

#include "dataset/atomic_file.h"
#include "dataset/formats/image_io.h"
#include "dataset/formats/scene_io.h"
#include "dataset/gaussian_cloud.h"
#include "tests/app/cli_run.h"
#include "tests/test_paths.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

using pg::test::Run;
Run run(const std::string& args) { return pg::test::run_cli(args); }

void write_labels(const fs::path& ply, const std::vector<int32_t>& labels) {
    pg::data::GaussianCloud c;
    c.resize(labels.size());
    for (size_t i = 0; i < labels.size(); ++i) c.mean[i] = glm::vec3(0.0f, float(i), 0.0f);
    c.set_int_property("instance", labels);
    fs::create_directories(ply.parent_path());
    pg::data::write_ply(c, ply);
}

// SUITE/desk_000 with 4 Gaussians and one 2x2 view; PRED/desk_000 predicts it with one
// Gaussian and one pixel wrong: 3D IoU 1/2 (object 1: G={1,2}, P={1}), 2D IoU 1/2, OA 3/4.
void write_pair(const fs::path& suite, const fs::path& pred) {
    fs::create_directories(suite / "desk_000" / "masks");
    std::ofstream(suite / "suite.json") << json{{"suite", "desk"}, {"seed", 1}, {"task", "instance"},
                                                {"scenes", {"desk_000"}},
                                                {"split", {{"train", json::array()}, {"test", {"desk_000"}}}},
                                                {"classes", json::array()}}
                                               .dump();
    write_labels(suite / "desk_000" / "scene.ply", {0, 1, 1, 0});
    pg::data::write_png16(suite / "desk_000" / "masks" / "view_000.png", 2, 2, {0, 1, 1, 0});
    fs::create_directories(pred / "desk_000" / "masks");
    write_labels(pred / "desk_000" / "scene.ply", {0, 1, 0, 0});
    pg::data::write_png16(pred / "desk_000" / "masks" / "view_000.png", 2, 2, {0, 1, 0, 0});
}

}  // namespace

TEST_CASE("eval prints the paper's table and writes the JSON report") {
    const fs::path dir = pg::test::scratch("cli-eval");
    fs::remove_all(dir);
    write_pair(dir / "suite", dir / "pred");
    const fs::path report = dir / "eval.json";
    auto r = run("eval --gt " + (dir / "suite").string() + " --pred " + (dir / "pred").string() + " --json " +
                 report.string());
    INFO(r.out);
    REQUIRE(r.code == 0);
    CHECK(r.out.find("| scene | 3D | 2D | OA |") != std::string::npos);
    CHECK(r.out.find("| desk_000 | 50.00 | 50.00 | 75.00 |") != std::string::npos);
    const json j = json::parse(pg::data::read_text_file(report));
    CHECK(j["split"] == "test");
    CHECK(j["scenes"][0]["3d"]["miou"].get<double>() == Approx(0.5));
    CHECK(j["mean"]["oa"].get<double>() == Approx(0.75));
}

TEST_CASE("eval: bad input is one line naming the file with exit 1 and no JSON written") {
    const fs::path dir = pg::test::scratch("cli-eval-errors");
    fs::remove_all(dir);
    write_pair(dir / "suite", dir / "pred");
    const fs::path bad_mask = dir / "pred" / "desk_000" / "masks" / "view_000.png";
    pg::data::write_png16(bad_mask, 4, 1, {0, 1, 0, 0});
    const fs::path report = dir / "eval.json";
    auto r = run("eval --gt " + (dir / "suite").string() + " --pred " + (dir / "pred").string() + " --json " +
                 report.string());
    INFO(r.out);
    CHECK(r.code == 1);
    CHECK(r.out.rfind("error: ", 0) == 0);
    CHECK(r.out.find(bad_mask.string()) != std::string::npos);
    CHECK(pg::test::count_lines(r.out) == 1);
    CHECK_FALSE(fs::exists(report));

    auto s = run("eval --gt " + (dir / "suite").string() + " --pred " + (dir / "pred").string() + " --split val");
    INFO(s.out);
    CHECK(s.code != 0);
    CHECK(s.out.find("--split") != std::string::npos);
}

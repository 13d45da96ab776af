// PlayCanvas SOG through the CLI: a SOG scene renders as its decoded PLY does, and --lod picks a
// streamed scene's level.
#include <catch2/catch.hpp>

#include <filesystem>

#include "dataset/atomic_file.h"
#include "dataset/formats/scene_io.h"
#include "tests/app/cli_run.h"
#include "tests/test_paths.h"

namespace fs = std::filesystem;

namespace {

pg::test::Run run(const std::string& args) { return pg::test::run_cli(args); }
std::string sog(const std::string& name) { return (pg::test::fixtures() / "sog" / name).string(); }

}  // namespace

TEST_CASE("sog cli: a bundled SOG renders exactly as the PLY splat-transform decodes from it") {
    const auto dir = pg::test::scratch("cli-sog-render");
    fs::remove_all(dir);
    const std::string cams = (dir / "orbit.json").string();
    auto r = run("orbit " + sog("bundled_sh3.sog") + " --out " + cams + " --count 2 --width 96 --height 72 --up -y");
    INFO(r.out);
    REQUIRE(r.code == 0);
    for (const char* scene : {"bundled_sh3.sog", "bundled_sh3.decoded.ply"}) {
        r = run("render " + sog(scene) + " --cameras " + cams + " --out " + (dir / scene).string());
        INFO(r.out);
        REQUIRE(r.code == 0);
    }
    size_t views = 0;
    for (const auto& e : fs::directory_iterator(dir / "bundled_sh3.sog")) {
        if (e.path().extension() != ".png") continue;
        ++views;
        INFO(e.path().filename());
        CHECK(pg::data::read_file(e.path()) == pg::data::read_file(dir / "bundled_sh3.decoded.ply" / e.path().filename()));
    }
    CHECK(views == 2);
}

TEST_CASE("sog cli: --lod picks a streamed scene's level, and a level it lacks is one clear error") {
    auto r = run("info " + sog("streamed") + " --lod 1");
    INFO(r.out);
    REQUIRE(r.code == 0);
    CHECK(r.out.find("sog        streamed, version 2") != std::string::npos);
    CHECK(r.out.find("lod levels 2: 0: 2314 1: 386 (loaded); environment 96") != std::string::npos);
    CHECK(r.out.find("gaussians  482") != std::string::npos);
    r = run("info " + sog("streamed/lod-meta.json") + " --lod 2");
    CHECK(r.code == 1);
    CHECK(r.out.find("lod-meta.json: LOD level 2 asked for; the scene has 2 (0 to 1)") != std::string::npos);
    r = run("info " + sog("streamed") + " --lod -1");
    CHECK(r.code != 0);
    CHECK(r.out.find("--lod") != std::string::npos);
}

TEST_CASE("sog cli: segment --export-format sog writes scene.sog and one SOG per object, as the PLY export's") {
    const auto dir = pg::test::scratch("cli-sog-segment");
    fs::remove_all(dir);
    auto r = run("synth --suite desk --scenes 1 --seed 31 --density 0.03 --sh-degree 1 --cameras 4 --previews 1 --out " +
                 (dir / "suite").string());
    INFO(r.out);
    REQUIRE(r.code == 0);
    const std::string scene = (dir / "suite" / "desk_000").string();
    r = run("prompts " + scene + " --out " + (dir / "prompts.json").string());
    REQUIRE(r.code == 0);
    for (const char* format : {"ply", "sog"}) {
        r = run("segment " + scene + "/scene.ply --cameras " + scene + "/cameras.json --prompts " +
                (dir / "prompts.json").string() + " --model ground-truth --decoder ptv3 --views none --export-format " +
                format + " --out " + (dir / format).string());
        INFO(r.out);
        REQUIRE(r.code == 0);
    }
    CHECK_FALSE(fs::exists(dir / "sog" / "scene.ply"));
    const auto original = pg::data::load_scene(scene + "/scene.ply");
    const auto whole = pg::data::load_scene(dir / "sog" / "scene.sog");
    CHECK(whole.size() == original.size());
    CHECK(whole.sh_degree == 1);
    size_t objects = 0;
    for (const auto& e : fs::directory_iterator(dir / "ply" / "objects")) {
        const fs::path sog_file = dir / "sog" / "objects" / e.path().filename().replace_extension(".sog");
        INFO(sog_file);
        REQUIRE(fs::exists(sog_file));
        CHECK(pg::data::load_scene(sog_file).size() == pg::data::load_scene(e.path()).size());
        ++objects;
    }
    CHECK(objects >= 3);
    r = run("segment " + scene + "/scene.ply --cameras " + scene + "/cameras.json --prompts " + (dir / "prompts.json").string() +
            " --model ground-truth --views none --export-format gltf --out " + (dir / "bad").string());
    CHECK(r.code == 1);
    CHECK(r.out.find("--export-format: expected ply or sog, got 'gltf'") != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "bad"));
}

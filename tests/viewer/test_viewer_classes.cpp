// Label by class in pointgauss-viewer end to end under Xvfb (lavapipe, validation on): the
// semantic model's classes arrive as `segment --semantic` gives them, tint the view, turn into
// objects that clicks then correct, and export; a missing or wrong model is one clear error.
// The model is the shipped assets/models/semantic.safetensors when present, else a tiny one
// `train` writes here from a synthetic campus suite.
#include <catch2/catch.hpp>

#include <algorithm>
#include <set>

#include "dataset/eval/label_files.h"
#include "dataset/json_file.h"
#include "tests/test_paths.h"
#include "tests/viewer/viewer_run.h"

namespace fs = std::filesystem;
using nlohmann::json;
using pg::test::Run;

namespace {

struct Campus {
    fs::path scene, model;
};

// A small synthetic campus scene (cameras beside it) and a semantic model for it.
Campus campus(const fs::path& dir) {
    const fs::path suite = dir / "suite";
    Run synth = pg::test::run_cli("synth --suite campus --scenes 2 --seed 9 --density 0.015 --cameras 3 --width 64 "
                                  "--height 48 --previews 1 --out " + suite.string());
    INFO(synth.out);
    REQUIRE(synth.code == 0);
    Campus c{suite / "campus_001" / "scene.ply", pg::test::source_dir() / "assets" / "models" / "semantic.safetensors"};
    if (!fs::exists(c.model)) {
        c.model = dir / "semantic.safetensors";
        Run train = pg::test::run_cli("train --data " + suite.string() + " --steps 2 --batch 1 --points 1024 "
                                      "--val-samples 1 --calibration 1 --out " + c.model.string());
        INFO(train.out);
        REQUIRE(train.code == 0);
    }
    return c;
}

size_t count(const std::vector<int32_t>& v, int32_t x) { return size_t(std::count(v.begin(), v.end(), x)); }

}  // namespace

TEST_CASE("label by class in the viewer tints the classes, makes objects of them that clicks correct, and exports them",
          "[viewer]") {
    const fs::path dir = pg::test::process_scratch("viewer-classes");
    const Campus c = campus(dir);
    // What segment --semantic gives: the viewer must label every Gaussian the same.
    Run cli = pg::test::run_cli("segment " + c.scene.string() + " --cameras " +
                                (c.scene.parent_path() / "cameras.json").string() + " --semantic --model " +
                                c.model.string() + " --views none --out " + (dir / "cli").string());
    INFO(cli.out);
    REQUIRE(cli.code == 0);
    const auto expected = pg::data::eval::read_gaussian_labels(dir / "cli" / "scene.ply", "class");
    int chosen = 1;  // the most populous class but 0 (untinted)
    for (int k = 2; k <= *std::max_element(expected.begin(), expected.end()); ++k)
        if (count(expected, k) > count(expected, chosen)) chosen = k;
    REQUIRE(count(expected, chosen) > 0);

    auto shot = [&](const char* name) { return json{{"screenshot", (dir / name).string()}, {"view", true}}; };
    auto labels_only = [&](const char* name) {
        return json{{"export", {{"folder", (dir / name).string()}, {"masks", false}, {"objects", false}}}};
    };
    const json centre = {0.5, 0.55};
    auto script = pg::test::write_script(dir, json::array({{{"snap", 0}},
                                                           {{"mask", false}},
                                                           shot("plain.png"),
                                                           {{"label_by_class", true}},
                                                           shot("tinted.png"),
                                                           {{"class_tints", false}},
                                                           shot("untinted.png"),
                                                           {{"class_tints", true}},
                                                           {{"object_from_class", chosen}},
                                                           labels_only("whole"),
                                                           {{"delete", true}},
                                                           {{"object_from_class", centre}},
                                                           labels_only("region"),
                                                           {{"click", centre}, {"negative", true}},
                                                           labels_only("corrected")}));
    Run r = pg::test::run_viewer(c.scene.string() + " --semantic-model " + c.model.string() +
                                 " --size 640x400 --script " + script.string());
    INFO(r.out);
    REQUIRE(r.code == 0);

    // Labels arrive: the classes of segment --semantic, in the exported scene's `class` property.
    const auto classes = pg::data::eval::read_gaussian_labels(dir / "whole" / "scene.ply", "class");
    CHECK(classes == expected);
    const json report = pg::data::read_json_file(dir / "whole" / "report.json");
    CHECK(report["classes"][size_t(chosen)]["gaussians"] == count(expected, chosen));

    // The tints change the picture where classes other than 0 are; hidden, the picture is the plain one.
    auto plain = pg::data::read_png8(dir / "plain.png");
    auto tinted = pg::data::read_png8(dir / "tinted.png");
    auto changed = pg::test::changed(plain, tinted, 64, 40);
    CHECK(std::count(changed.begin(), changed.end(), true) > 64 * 40 / 20);
    CHECK(pg::data::read_png8(dir / "untinted.png").pixels == plain.pixels);

    // The whole class became object 1: its Gaussians exactly.
    const auto whole = pg::data::eval::read_gaussian_labels(dir / "whole" / "scene.ply", "instance");
    CHECK(count(whole, 1) == count(expected, chosen));
    for (size_t g = 0; g < whole.size(); ++g)
        if ((whole[g] == 1) != (expected[g] == chosen))
            FAIL("Gaussian " << g << " object " << whole[g] << " class " << expected[g]);
    CHECK(report["objects"][0]["from"] == "class " + report["classes"][size_t(chosen)]["name"].get<std::string>());

    // Object 1 deleted, the connected region under the centre became object 2: part of one class.
    const auto region = pg::data::eval::read_gaussian_labels(dir / "region" / "scene.ply", "instance");
    std::set<int32_t> region_classes;
    for (size_t g = 0; g < region.size(); ++g)
        if (region[g] == 2) region_classes.insert(expected[g]);
    REQUIRE(region_classes.size() == 1);
    const int region_class = *region_classes.begin();
    const size_t in_region = count(region, 2);
    CHECK(in_region <= count(expected, region_class));
    CHECK(count(region, 1) == 0);

    // A negative click on it (object 2 is selected) takes the part under the click away.
    const auto corrected = pg::data::eval::read_gaussian_labels(dir / "corrected" / "scene.ply", "instance");
    INFO("region " << in_region << ", after the negative click " << count(corrected, 2));
    CHECK(count(corrected, 2) < in_region);
    for (size_t g = 0; g < corrected.size(); ++g)
        if (corrected[g] == 2 && region[g] != 2) FAIL("a negative click added Gaussian " << g);
    fs::remove_all(dir);  // this process's alone; kept above when a check stops the test
}

TEST_CASE("label by class in the viewer refuses a missing or wrong model with one clear error", "[viewer]") {
    const fs::path dir = pg::test::scratch("viewer-classes-errors");
    const fs::path desk = pg::test::source_dir() / "assets" / "sample" / "desk_000" / "scene.ply";
    Run missing = pg::test::run_viewer(desk.string() + " --semantic-model " + (dir / "missing.safetensors").string());
    CHECK(missing.code == 1);
    CHECK(missing.out.find("--semantic-model") != std::string::npos);
    CHECK(missing.out.find("missing.safetensors") != std::string::npos);
    CHECK(missing.out.find("vulkan validation") == std::string::npos);  // the window it opened is closed cleanly

    // An interactive model is not a semantic one: the action fails with that reason, the viewer does not crash.
    const fs::path interactive = pg::test::source_dir() / "assets" / "models" / "interactive.safetensors";
    auto wrong = pg::test::write_script(dir, json::array({{{"label_by_class", interactive.string()}}}));
    Run r = pg::test::run_viewer(desk.string() + " --size 640x400 --script " + wrong.string());
    INFO(r.out);
    CHECK(r.code == 1);
    CHECK(r.out.find("label by class failed") != std::string::npos);
    CHECK(r.out.find("not a semantic model") != std::string::npos);

    auto early = pg::test::write_script(dir, json::array({{{"object_from_class", "building"}}}));
    Run e = pg::test::run_viewer(desk.string() + " --size 640x400 --script " + early.string());
    CHECK(e.code == 1);
    CHECK(e.out.find("run label_by_class first") != std::string::npos);
}

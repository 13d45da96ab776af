// Script files: every action the viewer knows parses; mistakes are named by file and action.
#include <catch2/catch.hpp>

#include <fstream>

#include "app/viewer/script.h"
#include "dataset/error.h"
#include "tests/test_paths.h"

namespace {
std::filesystem::path write(const std::string& name, const std::string& text) {
    auto p = pg::test::scratch("viewer-script") / name;
    std::ofstream(p) << text;
    return p;
}
std::string error_of(const std::string& text) {
    try {
        pg::viewer::read_script(write("bad.json", text));
    } catch (const pg::data::InputError& e) {
        return e.what();
    }
    return "";
}
}  // namespace

TEST_CASE("a script with every action parses in order", "[viewer]") {
    auto actions = pg::viewer::read_script(write("all.json", R"({"actions": [
        {"snap": 0}, {"snap": "view_001"}, {"orbit": [10, -5]}, {"pan": [0.1, 0]}, {"zoom": 0.8},
        {"frame": true}, {"new_object": "mug"}, {"click": [0.5, 0.5]}, {"click_pixel": [10, 20], "negative": true},
        {"select": 1}, {"pick": [0.5, 0.5]}, {"rename": "cup"}, {"recolour": [1, 0, 0]}, {"hide": false}, {"isolate": true},
        {"tints": true}, {"mask": false}, {"decoder": "ground-truth"}, {"undo": 2}, {"redo": 1},
        {"export": "out"}, {"export": {"folder": "o2", "masks": false}}, {"screenshot": "a.png", "view": true},
        {"delete": true}, {"export": {"folder": "o3", "format": "sog"}}, {"open": {"scene": "x.sog", "lod": 1}}]})"));
    REQUIRE(actions.size() == 26);
    REQUIRE(actions[8].kind == "click_pixel");
    REQUIRE(actions[8].extra.value("negative", false));
    REQUIRE(actions[22].extra.value("view", false));
}

TEST_CASE("script errors name the file, the action and the reason", "[viewer]") {
    REQUIRE(error_of(R"({"steps": []})").find("expected {\"actions\"") != std::string::npos);
    auto e = error_of(R"({"actions": [{"snap": 0}, {"clik": [0.5, 0.5]}]})");
    REQUIRE(e.find("bad.json: action 1") != std::string::npos);
    REQUIRE(e.find("unknown action 'clik'") != std::string::npos);
    REQUIRE(error_of(R"({"actions": [{"click": [0.5]}]})").find("two numbers") != std::string::npos);
    REQUIRE(error_of(R"({"actions": [{"zoom": -1}]})").find("factor > 0") != std::string::npos);
    REQUIRE(error_of(R"({"actions": [{"snap": 0, "zoom": 2}]})").find("names two actions") != std::string::npos);
    REQUIRE(error_of(R"({"actions": [{"negative": true}]})").find("names no action") != std::string::npos);
    REQUIRE(error_of(R"({"actions": [{"hide": "yes"}]})").find("true or false") != std::string::npos);
    REQUIRE(error_of("{not json").find("bad.json") != std::string::npos);
    REQUIRE(error_of(R"({"actions": [{"open": {"scene": "x.sog", "lod": -1}}]})").find("'open' expects") != std::string::npos);
    REQUIRE(error_of(R"({"actions": [{"export": {"folder": "o", "format": "gltf"}}]})").find("\"ply\" or \"sog\"") !=
            std::string::npos);
}

TEST_CASE("label by class actions parse, and their mistakes are named", "[viewer]") {
    auto actions = pg::viewer::read_script(write("classes.json", R"({"actions": [
        {"label_by_class": true}, {"label_by_class": "semantic.safetensors"}, {"class_tints": false},
        {"object_from_class": "building"}, {"object_from_class": 2}, {"object_from_class": [0.5, 0.4]}]})"));
    REQUIRE(actions.size() == 6);
    CHECK(actions[1].value == "semantic.safetensors");
    CHECK(actions[5].kind == "object_from_class");
    CHECK(error_of(R"({"actions": [{"label_by_class": false}]})").find("true or a semantic model") !=
          std::string::npos);
    CHECK(error_of(R"({"actions": [{"object_from_class": [0.5]}]})").find("class name or id") != std::string::npos);
    CHECK(error_of(R"({"actions": [{"class_tints": 1}]})").find("true or false") != std::string::npos);
}

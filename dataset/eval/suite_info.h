#pragma once
// The parts of a benchmark folder (written by `pointgauss synth`) that evaluation reads:
// SUITE_DIR/suite.json and SUITE_DIR/<scene>/meta.json.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace pg::data::eval {

struct ClassInfo {
    int32_t id = 0;
    std::string name;
};

struct SuiteInfo {
    std::string suite;  // desk | vehicles | residence | campus
    std::string task;   // instance | semantic
    uint64_t seed = 0;
    std::vector<std::string> scenes, train, test;
    std::vector<ClassInfo> classes;
    // Set by `eval --two-class` (two_class.h): scores see this class against background, and
    // `classes` holds those two; `own_classes` keeps the suite's, which a prediction names.
    std::optional<ClassInfo> two_class;
    std::vector<ClassInfo> own_classes;

    bool semantic() const { return task == "semantic"; }
    // The per-Gaussian PLY property and mask meaning of the task: "instance" or "class".
    const char* label_property() const { return semantic() ? "class" : "instance"; }
    // "test", "train" or "all" (every scene); std::invalid_argument for anything else.
    const std::vector<std::string>& split(const std::string& which) const;
};

// Throws InputError naming suite.json if it is missing or malformed, or a scene name is
// not a plain folder name.
SuiteInfo read_suite_json(const std::filesystem::path& suite_dir);

struct InstanceInfo {
    int32_t id = 0;
    int32_t class_id = 0;
    std::string name;
};

// From meta.json: the GT objects (names for the report, ids that count even when a view
// misses them). A missing meta.json gives an empty list; a malformed one an InputError.
std::vector<InstanceInfo> read_scene_instances(const std::filesystem::path& scene_dir);

}  // namespace pg::data::eval

#include "dataset/eval/suite_info.h"

#include <stdexcept>

#include <nlohmann/json.hpp>

#include "dataset/atomic_file.h"
#include "dataset/error.h"
#include "dataset/json_file.h"

namespace pg::data::eval {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// Scene names become folder names: refuse anything that could leave the suite folder.
void check_scene_name(const fs::path& file, const std::string& name) {
    if (name.empty() || name == "." || name == ".." || name.find('/') != std::string::npos ||
        name.find('\\') != std::string::npos)
        throw InputError(file.string(), "scene name '" + name + "' is not a plain folder name");
}

std::vector<std::string> scene_list(const fs::path& file, const json& j) {
    auto names = j.get<std::vector<std::string>>();
    for (auto& n : names) check_scene_name(file, n);
    return names;
}

}  // namespace

const std::vector<std::string>& SuiteInfo::split(const std::string& which) const {
    if (which == "test") return test;
    if (which == "train") return train;
    if (which == "all") return scenes;
    throw std::invalid_argument("unknown split '" + which + "' (test, train or all)");
}

SuiteInfo read_suite_json(const fs::path& suite_dir) {
    const fs::path file = suite_dir / "suite.json";
    const json j = read_json_file(file);
    SuiteInfo s;
    try {
        if (!j.is_object()) throw InputError(file.string(), "expected a JSON object");
        for (const char* key : {"suite", "task", "scenes", "split"})
            if (!j.contains(key)) throw InputError(file.string(), std::string("missing \"") + key + "\"");
        s.suite = j.at("suite").get<std::string>();
        s.task = j.at("task").get<std::string>();
        if (s.task != "instance" && s.task != "semantic")
            throw InputError(file.string(), "task '" + s.task + "' is neither instance nor semantic");
        s.seed = j.value("seed", uint64_t(0));
        s.scenes = scene_list(file, j.at("scenes"));
        const json& split = j.at("split");
        if (split.contains("train")) s.train = scene_list(file, split.at("train"));
        if (split.contains("test")) s.test = scene_list(file, split.at("test"));
        for (const json& c : j.value("classes", json::array()))
            s.classes.push_back({c.at("id").get<int32_t>(), c.value("name", std::string())});
    } catch (const json::exception& e) {
        throw InputError(file.string(), e.what());
    }
    return s;
}

std::vector<InstanceInfo> read_scene_instances(const fs::path& scene_dir) {
    const fs::path file = scene_dir / "meta.json";
    if (!fs::exists(file)) return {};
    const json j = read_json_file(file);
    std::vector<InstanceInfo> out;
    try {
        for (const json& i : j.value("instances", json::array()))
            out.push_back({i.at("id").get<int32_t>(), i.value("class", int32_t(0)), i.value("name", std::string())});
    } catch (const json::exception& e) {
        throw InputError(file.string(), e.what());
    }
    return out;
}

}  // namespace pg::data::eval

// Scene folders and the suite index of the benchmark contract.
#include <algorithm>
#include <ostream>

#include <nlohmann/json.hpp>

#include "dataset/atomic_file.h"
#include "dataset/error.h"
#include "dataset/formats/camera_io.h"
#include "dataset/formats/image_io.h"
#include "dataset/formats/scene_io.h"
#include "dataset/synth/synth.h"

namespace pg::data::synth {

namespace fs = std::filesystem;

namespace {

nlohmann::ordered_json classes_json(const std::vector<ClassInfo>& classes) {
    auto j = nlohmann::ordered_json::array();
    for (const ClassInfo& c : classes) j.push_back({{"id", c.id}, {"name", c.name}});
    return j;
}

void write_json(const fs::path& path, const nlohmann::ordered_json& j) {
    write_atomically(path, [&](std::ostream& out) { out << j.dump(2) << "\n"; });
}

void make_dir(const fs::path& dir) {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw InputError(dir.string(), "cannot create folder: " + ec.message());
}

}  // namespace

void write_scene(const SynthScene& scene, const fs::path& dir) {
    make_dir(dir);
    write_ply(scene.cloud, dir / "scene.ply");
    write_inria_cameras_json(scene.cameras, dir / "cameras.json");
    write_colmap_binary(scene.cameras, dir / "sparse" / "0");
    if (!scene.masks.empty()) {
        make_dir(dir / "masks");
        for (size_t i = 0; i < scene.cameras.size() && i < scene.masks.size(); ++i) {
            const Camera& c = scene.cameras[i];
            write_png16(dir / "masks" / (c.name + ".png"), c.width, c.height, scene.masks[i]);
        }
    }
    nlohmann::ordered_json meta;
    meta["name"] = scene.name;
    meta["suite"] = suite_name(scene.suite);
    meta["task"] = suite_task(scene.suite);
    meta["seed"] = scene.seed;
    meta["index"] = scene.index;
    meta["scene_seed"] = scene.scene_seed;
    meta["up"] = {scene.up.x, scene.up.y, scene.up.z};
    meta["scale"] = scene.scale;
    meta["centre"] = {scene.centre.x, scene.centre.y, scene.centre.z};
    auto instances = nlohmann::ordered_json::array();
    for (const InstanceInfo& i : scene.instances)
        instances.push_back({{"id", i.id}, {"class", i.cls}, {"name", i.name}, {"gaussians", i.gaussians}});
    meta["instances"] = instances;
    meta["classes"] = classes_json(scene.classes);
    meta["gaussians"] = scene.cloud.size();
    meta["sh_degree"] = scene.cloud.sh_degree;
    meta["cameras"] = scene.cameras.size();
    const int w = scene.cameras.empty() ? 0 : scene.cameras[0].width, h = scene.cameras.empty() ? 0 : scene.cameras[0].height;
    meta["image_size"] = {w, h};
    write_json(dir / "meta.json", meta);
}

SuiteSplit split_suite(const std::vector<std::string>& scenes, uint64_t seed) {
    const size_t n = scenes.size();
    size_t tests = n < 2 ? 0 : std::max<size_t>(1, (n + 2) / 5);  // round(n / 5), at least one
    std::vector<size_t> order(n);
    for (size_t i = 0; i < n; ++i) order[i] = i;
    Rng rng(derive_seed(seed, 0x5B1177));
    for (size_t i = n; i > 1; --i) std::swap(order[i - 1], order[size_t(rng.next() % i)]);
    std::vector<bool> is_test(n, false);
    for (size_t k = 0; k < tests; ++k) is_test[order[k]] = true;
    SuiteSplit split;
    for (size_t i = 0; i < n; ++i) (is_test[i] ? split.test : split.train).push_back(scenes[i]);
    return split;
}

void write_suite_index(SuiteKind suite, uint64_t seed, const std::vector<std::string>& scenes, const fs::path& suite_dir) {
    make_dir(suite_dir);
    const SuiteSplit split = split_suite(scenes, seed);
    nlohmann::ordered_json j;
    j["suite"] = suite_name(suite);
    j["seed"] = seed;
    j["task"] = suite_task(suite);
    j["scenes"] = scenes;
    j["split"] = {{"train", split.train}, {"test", split.test}};
    j["classes"] = classes_json(suite_classes(suite));
    write_json(suite_dir / "suite.json", j);
}

}  // namespace pg::data::synth

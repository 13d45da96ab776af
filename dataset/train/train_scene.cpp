#include "dataset/train/train_scene.h"

#include <algorithm>
#include <stdexcept>

#include "dataset/error.h"
#include "dataset/eval/suite_info.h"
#include "dataset/formats/camera_io.h"
#include "dataset/formats/scene_io.h"
#include "dataset/semantic/gaussian_features.h"
#include "dataset/up_axis.h"

namespace pg::data::train {

namespace fs = std::filesystem;

namespace {

// Whether a scene folder holds cameras in a place load_cameras looks; a folder without any
// is trained like a bare PLY rather than refused.
bool has_camera_files(const fs::path& dir) {
    for (const char* f : {"cameras.json", "transforms.json", "sparse", "cameras.bin", "cameras.txt"})
        if (fs::exists(dir / f)) return true;
    return false;
}

}  // namespace

SceneFiles read_scene_files(const fs::path& path) {
    std::error_code ec;
    if (!fs::exists(path, ec)) throw InputError(path.string(), "no such file or folder");
    const bool folder = fs::is_directory(path, ec);
    SceneFiles f;
    f.ply = folder ? path / "scene.ply" : path;
    if (folder && !fs::is_regular_file(f.ply, ec))
        throw InputError(path.string(), "not a scene folder: it holds no scene.ply");
    f.name = folder ? fs::absolute(path).lexically_normal().filename().string() : path.stem().string();
    if (f.name.empty()) f.name = fs::absolute(path).lexically_normal().parent_path().filename().string();
    if (folder && has_camera_files(path)) f.cameras = load_cameras(path);
    return f;
}

glm::dvec3 scene_up(const std::vector<Camera>& cameras, const GaussianCloud& cloud) {
    if (cameras.empty()) return up_from_ground_plane(cloud);
    try {
        return up_from_cameras(cameras);
    } catch (const InputError&) {  // cameras all around (no common up): fall back to the ground
        return up_from_ground_plane(cloud);
    }
}

TrainScene load_train_scene(const fs::path& path, std::optional<glm::dvec3> up,
                            const std::vector<std::string>& feature_groups) {
    const SceneFiles files = read_scene_files(path);
    TrainScene s;
    s.source = files.ply;
    s.name = files.name;
    const GaussianCloud cloud = load_scene(files.ply);  // names the file on any read error
    auto instance = cloud.int_property("instance");
    if (!instance) throw InputError(files.ply.string(), "has no integer \"instance\" property (per-Gaussian object ids)");
    if (std::none_of(instance->begin(), instance->end(), [](int32_t id) { return id > 0; }))
        throw InputError(files.ply.string(), "labels no object: every \"instance\" id is 0 (background) or negative");
    s.instance = std::move(*instance);
    s.positions = cloud.mean;
    for (const Camera& c : files.cameras) s.camera_positions.push_back(c.position());
    if (up) {
        if (!(glm::length(*up) > 0)) throw std::invalid_argument("load_train_scene: up must be non-zero");
        s.up = glm::normalize(*up);
    } else {
        s.up = scene_up(files.cameras, cloud);
    }
    if (!feature_groups.empty()) {
        s.feature_groups = feature_groups;
        s.features = semantic::raw_gaussian_features(cloud, {}, feature_groups, s.up);
    }
    return s;
}

std::vector<fs::path> find_train_scenes(const std::vector<fs::path>& paths, const std::string& split) {
    std::vector<fs::path> out;
    for (const fs::path& p : paths) {
        std::error_code ec;
        if (fs::is_directory(p, ec) && fs::exists(p / "suite.json", ec)) {
            const eval::SuiteInfo suite = eval::read_suite_json(p);
            const std::vector<std::string>* names = nullptr;
            try {
                names = &suite.split(split);
            } catch (const std::invalid_argument& e) {
                throw InputError("--split", e.what());
            }
            for (const std::string& n : *names) out.push_back(p / n);
        } else if (fs::is_directory(p, ec) && fs::exists(p / "scene.ply", ec)) {
            out.push_back(p);
        } else if (fs::is_regular_file(p, ec)) {
            out.push_back(p);
        } else if (!fs::exists(p, ec)) {
            throw InputError(p.string(), "no such file or folder");
        } else {
            throw InputError(p.string(), "not a suite folder (suite.json), a scene folder (scene.ply) or a PLY file");
        }
    }
    return out;
}

}  // namespace pg::data::train

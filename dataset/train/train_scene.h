#pragma once
// Labelled scenes for training the interactive model: what sample drawing needs from a
// scene (Gaussian centres, instance ids, camera positions, up) and nothing else, so a
// training set of many scenes stays small in memory.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "dataset/camera.h"
#include "dataset/gaussian_cloud.h"

namespace pg::data::train {

struct TrainScene {
    std::string name;                          // scene folder name, or the PLY's stem
    std::filesystem::path source;              // the PLY read
    std::vector<glm::vec3> positions;          // Gaussian centres
    std::vector<int32_t> instance;             // per Gaussian; 0 = background, > 0 = an object
    std::vector<glm::dvec3> camera_positions;  // empty for a bare PLY
    glm::dvec3 up{0, -1, 0};                   // unit
    // Raw per-Gaussian rows of the feature groups an interactive model reads (semantic/
    // gaussian_features.h, before its unit): empty unless asked for at load.
    std::vector<std::string> feature_groups;
    std::vector<float> features;

    size_t size() const { return positions.size(); }
    bool has_cameras() const { return !camera_positions.empty(); }
};

// A scene folder (scene.ply plus cameras: sparse/0, cameras.json or transforms.json, as
// load_cameras finds them) or a bare PLY. The PLY needs an integer "instance" property with
// at least one object (id > 0). Up: `up` if given, else the cameras' mean up, else (no
// cameras, or cameras too disagreeing to say) a ground-plane fit. Throws InputError naming
// the path and the reason. `feature_groups`: the rows to keep for a model that reads them.
TrainScene load_train_scene(const std::filesystem::path& dir_or_ply, std::optional<glm::dvec3> up = std::nullopt,
                            const std::vector<std::string>& feature_groups = {});

// What the training tasks share when they read a scene: a scene folder's scene.ply (or the PLY
// itself), its name (the folder's, or the PLY's stem), the folder's cameras (none for a bare PLY
// or a folder without camera files), and the up rule: the cameras' mean up, else (no cameras, or
// cameras all around) a ground-plane fit. Throws InputError naming the path.
struct SceneFiles {
    std::filesystem::path ply;
    std::string name;
    std::vector<Camera> cameras;
};
SceneFiles read_scene_files(const std::filesystem::path& dir_or_ply);
glm::dvec3 scene_up(const std::vector<Camera>& cameras, const GaussianCloud& cloud);

// Expands each path: a suite folder (suite.json) into its scenes of `split` ("train",
// "test" or "all"), a scene folder (scene.ply) or a PLY file into itself. Order is kept
// (suite order within a suite). Throws InputError for a path that is none of these, a
// malformed suite.json or an unknown split.
std::vector<std::filesystem::path> find_train_scenes(const std::vector<std::filesystem::path>& paths,
                                                     const std::string& split);

}  // namespace pg::data::train

#pragma once
// Training samples for the semantic model, drawn the way `segment --semantic` builds its inputs
// (dataset/semantic/scene_tiles.h): a tile column of the scene, its network frame, one
// partition batch's worth of its Gaussians, their appearance features, and their classes.
// The column's centre is a random Gaussian's, moved by up to half a tile, so tiles land on the
// scene as the inference grid does: everywhere there is content, in every alignment. A share of
// the draws (`balance`) first picks a class present in the scene uniformly, then one of its
// Gaussians, so rare classes (a sports field's few hundred Gaussians among 300 k) are seen.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "dataset/random.h"

namespace pg::data::train {

struct SemanticOptions {
    uint32_t max_points = 8192;  // N_max
    double tile = 64.0;          // tile side, world units (the model config's tile_size)
    double grid = 0.01;          // voxel side, frame units (the model config's grid_size)
    std::vector<std::string> features;  // feature groups (dataset/semantic/gaussian_features.h)

    bool rotate = true, flip = true, scale = true, jitter = true, colour = true;
    double scale_min = 0.9, scale_max = 1.1;
    double jitter_sigma = 0.002, jitter_clip = 0.01;  // frame units
    double brightness = 0.2, tint = 0.05;             // rgb x U(1 +- brightness) x per channel U(1 +- tint)
    double balance = 0.5;                             // share of class-balanced column centres

    double unit() const { return tile * grid; }  // the feature unit: one voxel in world units
    SemanticOptions without_augmentation() const {
        SemanticOptions o = *this;
        o.rotate = o.flip = o.scale = o.jitter = o.colour = false;
        return o;
    }
};

// What drawing needs from a labelled scene, features computed once at load.
struct SemanticScene {
    std::string name;
    std::vector<glm::vec3> positions;
    std::vector<float> features;   // [n, channels]
    std::vector<int32_t> classes;  // per Gaussian
    glm::dvec3 up{0, 0, 1};
    size_t size() const { return positions.size(); }
};

// A scene folder (scene.ply with an integer "class" property; up from its cameras, else a
// ground-plane fit) or a bare PLY. InputError naming the file and the reason.
SemanticScene load_semantic_scene(const std::filesystem::path& dir_or_ply, const SemanticOptions& options);

struct SemanticSample {
    std::vector<float> coord;          // [n, 3] augmented frame coordinates
    std::vector<float> feat;           // [n, channels]
    std::vector<int32_t> labels;       // [n] classes
    std::vector<uint32_t> gaussians;   // scene indices, ascending
    size_t scene = 0;
    size_t column_points = 0;          // Gaussians in the column before the batch subset
    size_t size() const { return gaussians.size(); }
};

class SemanticDrawer {
public:
    // InputError if there are no scenes or a scene's classes exceed `classes`.
    SemanticDrawer(std::vector<SemanticScene> scenes, int classes, SemanticOptions options);
    const std::vector<SemanticScene>& scenes() const { return scenes_; }
    const SemanticOptions& options() const { return options_; }
    int classes() const { return classes_; }
    // The same generator state gives the same sample; threads may share a drawer.
    SemanticSample draw(Rng& rng) const;

private:
    std::vector<SemanticScene> scenes_;
    std::vector<std::vector<std::vector<uint32_t>>> by_class_;  // per scene, per class present: its Gaussians
    int classes_;
    SemanticOptions options_;
};

}  // namespace pg::data::train

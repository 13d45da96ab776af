#pragma once
// The automatic semantic mode: every Gaussian of a scene gets a class, without clicks. The
// scene is covered by tile columns (dataset/semantic/scene_tiles.h: stride half a tile, so each
// Gaussian lies in four); each tile's Gaussians are split into random batches of at most
// N_max (the same partition as the interactive ROI); the class network's softmax for every
// batch is summed per Gaussian over the tiles that hold it, and the argmax is its class.
// Batches are packed into multi-cloud forwards, so small tiles (sky, outskirts) cost little.
#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "dataset/gaussian_cloud.h"

namespace pg::seg {

// One batch of a tile: network coordinates (the tile's frame) and features, [n, 3] and [n, C].
struct ClassCloud {
    std::vector<float> coord, feat;
    size_t size() const { return coord.size() / 3; }
};

// A K-class network over several clouds at once (nn's PTv3 behind it, in app/).
class ClassNetwork {
public:
    virtual ~ClassNetwork() = default;
    virtual int classes() const = 0;
    virtual double tile_size() const = 0;          // world units
    virtual double voxel() const = 0;              // world units: the features' scale unit
    virtual std::vector<std::string> features() const = 0;
    // Softmax probabilities, [sum of sizes, classes], the clouds' points in order.
    virtual std::vector<float> probabilities(const std::vector<ClassCloud>& clouds) = 0;
};

struct SemanticLabelOptions {
    glm::dvec3 up{0, 0, 1};
    double tile = 0;                 // 0: the network's tile size
    uint32_t max_batch = 8192;       // N_max per batch
    uint32_t forward_points = 32768; // batches packed into one forward up to this many points
    uint64_t seed = 1;               // partition
    const std::atomic<bool>* cancel = nullptr;
    // Called after each forward with the tiles finished and their count.
    std::function<void(size_t done, size_t total)> progress;
};

struct SemanticLabels {
    std::vector<int32_t> classes;     // per Gaussian
    std::vector<float> confidence;    // per Gaussian: the winning class's share of the votes (0: no vote)
    std::vector<size_t> class_counts; // Gaussians per class
    size_t tiles = 0, batches = 0, forwards = 0;
    size_t unvoted = 0;               // Gaussians no tile held (non-finite centres): class 0
    std::map<std::string, double> stage_ms;  // "features", "tiles", "network"
};

// std::invalid_argument when up is zero or the sizes are not positive.
SemanticLabels label_by_class(const data::GaussianCloud& cloud, ClassNetwork& network,
                              const SemanticLabelOptions& options);

}  // namespace pg::seg

#pragma once
// What "label by class" leaves in the viewer: a class per Gaussian from the semantic model
// (engine/segment/semantic_labeler.h) with the model's class names, and the regions of a class
// an object can be made from (Document's Region).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "app/viewer/document.h"

namespace pg::viewer {

struct ClassLabels {
    std::string model;               // the semantic model's file
    std::vector<std::string> names;  // per class, as the model names them
    std::vector<int32_t> classes;    // per Gaussian
    std::vector<float> confidence;   // per Gaussian: the winning class's share of the votes
    std::vector<size_t> counts;      // Gaussians per class
    std::string name(int c) const;   // names[c], else class_<c>
    // The class named `name`, or numbered so; -1 if none.
    int find(const std::string& name) const;
};

// A region of class `cls` for an object: every Gaussian of the class when `seed` < 0, else
// the connected part of the class that holds Gaussian `seed` (which must be of the class).
// Connected: the class's Gaussians are binned in cubes of kRegionCell times their median
// spacing (nearest-neighbour distance between centres), and cubes that touch (26-neighbours)
// join; so Gaussians closer than one cube always join, and parts more than two cube diagonals
// apart never do. Each Gaussian's claim is its class confidence. std::invalid_argument when
// the seed is not of the class.
inline constexpr float kRegionCell = 3.0f;
std::shared_ptr<const Region> class_region(const std::vector<glm::vec3>& means, const ClassLabels& labels, int cls,
                                           int64_t seed = -1);

}  // namespace pg::viewer

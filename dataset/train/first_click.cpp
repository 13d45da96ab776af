#include "dataset/train/first_click.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "dataset/clicks/components.h"
#include "dataset/clicks/kd_tree.h"

namespace pg::data::train {

FirstClickSet first_click_set(std::span<const glm::vec3> positions, std::span<const uint8_t> object,
                              float link_radius) {
    if (object.size() != positions.size())
        throw std::invalid_argument("first_click_set: the object mask has " + std::to_string(object.size()) +
                                    " entries for " + std::to_string(positions.size()) + " Gaussians");
    const clicks::Components parts = clicks::point_components(positions, object, link_radius);
    const int32_t largest = parts.largest();
    if (largest < 0) throw std::invalid_argument("first_click_set: the object has no Gaussians");

    FirstClickSet out;
    out.part.reserve(parts.size[largest]);
    for (size_t i = 0; i < positions.size(); ++i)
        if (parts.label[i] == largest) out.part.push_back(uint32_t(i));

    glm::dvec3 lo(positions[out.part[0]]), hi = lo;
    for (uint32_t i : out.part) {
        lo = glm::min(lo, glm::dvec3(positions[i]));
        hi = glm::max(hi, glm::dvec3(positions[i]));
    }
    const glm::dvec3 side = hi - lo;
    const double cap = std::max(0.5 * std::max({side.x, side.y, side.z}), double(link_radius));
    // Only Gaussians outside the part within the cap of its box can be nearer than the cap.
    std::vector<uint32_t> outside;
    for (size_t i = 0; i < positions.size(); ++i) {
        const glm::dvec3 p(positions[i]);
        if (parts.label[i] != largest && glm::all(glm::greaterThanEqual(p, lo - cap)) &&
            glm::all(glm::lessThanEqual(p, hi + cap)))
            outside.push_back(uint32_t(i));
    }
    const clicks::KdTree tree(positions, outside);

    out.depth.resize(out.part.size());
    float deepest = 0;
    for (size_t m = 0; m < out.part.size(); ++m) {
        out.depth[m] = float(std::sqrt(tree.nearest2(glm::dvec3(positions[out.part[m]]), cap * cap)));
        deepest = std::max(deepest, out.depth[m]);
    }
    const float threshold = float(kMinDepthFraction) * deepest;
    for (size_t m = 0; m < out.part.size(); ++m)
        if (out.depth[m] >= threshold) out.candidates.push_back(out.part[m]);
    return out;
}

}  // namespace pg::data::train

#pragma once
// Where a training sample's first click may go. The benchmark's rule (Clicker3D::first_click)
// picks the single most interior Gaussian of the object's largest connected part: one click,
// hence one ROI placement, per object, which a model trained on it would overfit to. Users
// click anywhere clearly inside an object, so training draws the click uniformly among the
// part's Gaussians at least half as deep as the deepest one: still well away from where the
// object touches something else (a click there would spread its positive weight onto the
// neighbour), yet spread over the object so the ROI and the click weights vary.
//
// Depth is the benchmark's interior distance: to the nearest Gaussian outside the part,
// capped at half the part's largest bounding-box side (deeper only means "stands apart").
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace pg::data::train {

// Candidates hold at least kMinDepthFraction x the part's largest depth.
constexpr double kMinDepthFraction = 0.5;

struct FirstClickSet {
    std::vector<uint32_t> part;        // the object's largest connected part, ascending
    std::vector<float> depth;          // interior distance of each part member
    std::vector<uint32_t> candidates;  // members with depth >= kMinDepthFraction x max, ascending
};

// `object` marks the object's Gaussians (one byte per position, non-empty); Gaussians closer
// than `link_radius` are connected (as in Clicker3D). Depths are capped no lower than the
// link radius, like the benchmark's.
FirstClickSet first_click_set(std::span<const glm::vec3> positions, std::span<const uint8_t> object,
                              float link_radius);

}  // namespace pg::data::train

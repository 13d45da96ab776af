#pragma once
// Simulated user clicks on Gaussians, the standard protocol of interactive 3D segmentation
// (InterObject3D, AGILE3D): each click at the most interior point of the largest error
// region, positive on a missed object part (false negative), negative on a wrongly taken
// part (false positive). The first click (empty prediction) is the same rule: the most
// interior point of the object's largest connected part.
//
// - Interior: distance from a member of a region to the nearest cloud point outside it,
//   capped at half the region's extent (see interior_point.h).
// - Regions: false negatives and false positives are split into components separately;
//   points closer than the link radius are one region. Splitting the ground truth too
//   keeps the first click off stray Gaussians (floaters) of the object, which stand
//   farthest from everything else.
// - Largest: the most points; ties -> the region holding the lowest index. Every other tie
//   also goes to the lowest index, so a click depends only on its inputs.
// - Never twice in one place: Gaussians already clicked count as outside every region, so the
//   next click lands at the point of its region farthest from both the region's boundary and
//   the earlier clicks (a person clicks elsewhere on a part that ignored a click); a region
//   of clicked Gaussians alone is passed over for the next largest. Without this rule a
//   click that leaves the prediction unchanged is repeated on the same Gaussian until the
//   session ends, and IoU-against-clicks curves go flat.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace pg::data::clicks {

struct Click3D {
    size_t index = 0;      // the clicked Gaussian
    glm::vec3 position{};  // its mean
    bool positive = true;  // inside the object (a missed part) or not (a wrong part)
};

// Default link radius in median nearest-neighbour distances: gaps in one surface's sampling
// stay inside a region, while parts a few spacings apart are separate regions.
constexpr float kLinkSpacings = 3.0f;

struct Clicker3DOptions {
    float link_radius = 0;  // scene units; 0: kLinkSpacings x the cloud's median spacing
};

class Clicker3D {
public:
    // Throws InputError if a position is not finite.
    explicit Clicker3D(std::span<const glm::vec3> positions, Clicker3DOptions options = {});

    size_t size() const { return positions_.size(); }
    float link_radius() const { return link_radius_; }

    // The next click for the current prediction; nullopt when it equals the ground truth.
    // Masks hold one byte per point, non-zero = inside; `clicked`: the Gaussians of the
    // session's earlier clicks. Throws InputError on a size mismatch.
    std::optional<Click3D> next_click(std::span<const uint8_t> gt, std::span<const uint8_t> prediction,
                                      std::span<const size_t> clicked = {}) const;
    // next_click with an empty prediction: the ground truth point farthest from every
    // point outside the ground truth (within its largest part); nullopt if gt is empty.
    std::optional<Click3D> first_click(std::span<const uint8_t> gt) const;

private:
    std::vector<glm::vec3> positions_;
    float link_radius_ = 0;
};

}  // namespace pg::data::clicks

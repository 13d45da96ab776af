#pragma once
// How the semantic mode covers a whole scene, shared by training and inference so the model
// sees the same inputs in both: square columns of side `tile` in the plane perpendicular to
// up, unbounded along up, on a grid of stride tile / 2, so every Gaussian lies in four tiles
// whose votes are summed. Only tiles that hold a Gaussian exist, so a sky dome or a far
// floater costs a tile of its own, never a grid over the empty space between.
//
// A tile's network frame (dataset/roi_frame.h) is centred on the tile, z up, in units of the
// tile side, its origin at the tile's ground: the 5 % quantile of its Gaussians' heights, so
// heights above ground read the same on a hill as in a valley.
#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

#include <glm/glm.hpp>

#include "dataset/roi_frame.h"

namespace pg::data::semantic {

constexpr double kGroundQuantile = 0.05;

// The frame of the column of side `tile` centred at `plane` (coordinates along the axes of
// data::horizontal_axes(up)) holding `members`.
RoiFrame tile_frame(std::span<const glm::vec3> positions, std::span<const uint32_t> members, glm::dvec3 up,
                    glm::dvec2 plane, double tile);

// The Gaussians whose centres lie in the column of side `tile` centred at `plane`, ascending.
std::vector<uint32_t> column_members(std::span<const glm::vec3> positions, glm::dvec3 up, glm::dvec2 plane,
                                     double tile);

// Coordinates of a point along the horizontal axes of up.
glm::dvec2 plane_coords(glm::dvec3 p, glm::dvec3 up);

class SceneTiling {
public:
    // std::invalid_argument unless tile > 0 and up is non-zero.
    SceneTiling(std::span<const glm::vec3> positions, glm::dvec3 up, double tile);

    size_t size() const { return tiles_.size(); }
    double tile() const { return tile_; }
    // Tile k's centre in plane coordinates and its Gaussians, ascending.
    glm::dvec2 centre(size_t k) const;
    std::vector<uint32_t> members(size_t k) const;
    RoiFrame frame(size_t k, std::span<const uint32_t> members) const {
        return tile_frame(positions_, members, up_, centre(k), tile_);
    }

private:
    std::span<const glm::vec3> positions_;
    glm::dvec3 up_;
    double tile_;
    std::vector<glm::ivec2> tiles_;  // lower-left stride cell of each tile
    std::unordered_map<uint64_t, std::vector<uint32_t>> cells_;  // stride cell -> Gaussians
};

}  // namespace pg::data::semantic

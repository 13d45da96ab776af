#include "dataset/semantic/scene_tiles.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "dataset/up_axis.h"

namespace pg::data::semantic {

namespace {

uint64_t cell_key(glm::ivec2 c) { return (uint64_t(uint32_t(c.x)) << 32) | uint64_t(uint32_t(c.y)); }

}  // namespace

glm::dvec2 plane_coords(glm::dvec3 p, glm::dvec3 up) {
    glm::dvec3 l, w;
    horizontal_axes(glm::normalize(up), l, w);
    return {glm::dot(p, l), glm::dot(p, w)};
}

RoiFrame tile_frame(std::span<const glm::vec3> positions, std::span<const uint32_t> members, glm::dvec3 up,
                    glm::dvec2 plane, double tile) {
    const glm::dvec3 u = glm::normalize(up);
    glm::dvec3 l, w;
    horizontal_axes(u, l, w);
    double ground = 0;
    if (!members.empty()) {
        std::vector<double> h(members.size());
        for (size_t i = 0; i < members.size(); ++i) h[i] = glm::dot(glm::dvec3(positions[members[i]]), u);
        const size_t q = size_t(kGroundQuantile * double(h.size() - 1));
        std::nth_element(h.begin(), h.begin() + std::ptrdiff_t(q), h.end());
        ground = h[q];
    }
    return RoiFrame::around(plane.x * l + plane.y * w + ground * u, u, tile);
}

std::vector<uint32_t> column_members(std::span<const glm::vec3> positions, glm::dvec3 up, glm::dvec2 plane,
                                     double tile) {
    glm::dvec3 l, w;
    horizontal_axes(glm::normalize(up), l, w);
    std::vector<uint32_t> out;
    for (size_t i = 0; i < positions.size(); ++i) {
        const glm::dvec3 p(positions[i]);
        if (std::abs(glm::dot(p, l) - plane.x) <= 0.5 * tile && std::abs(glm::dot(p, w) - plane.y) <= 0.5 * tile)
            out.push_back(uint32_t(i));
    }
    return out;
}

SceneTiling::SceneTiling(std::span<const glm::vec3> positions, glm::dvec3 up, double tile)
    : positions_(positions), tile_(tile) {
    if (!(tile > 0) || !std::isfinite(tile)) throw std::invalid_argument("SceneTiling: the tile side must be positive");
    if (!(glm::length(up) > 0)) throw std::invalid_argument("SceneTiling: up must be non-zero");
    up_ = glm::normalize(up);
    glm::dvec3 l, w;
    horizontal_axes(up_, l, w);
    const double stride = 0.5 * tile;
    for (size_t i = 0; i < positions.size(); ++i) {
        const glm::dvec3 p(positions[i]);
        const double a = std::floor(glm::dot(p, l) / stride), b = std::floor(glm::dot(p, w) / stride);
        if (!std::isfinite(a) || !std::isfinite(b) || std::abs(a) > 1e9 || std::abs(b) > 1e9) continue;
        cells_[cell_key({int(a), int(b)})].push_back(uint32_t(i));
    }
    // A point in stride cell c lies in the tiles whose lower-left cell is c - (0|1, 0|1).
    std::vector<uint64_t> keys;
    keys.reserve(4 * cells_.size());
    for (const auto& [key, _] : cells_) {
        const glm::ivec2 c(int32_t(uint32_t(key >> 32)), int32_t(uint32_t(key)));
        for (int dx = 0; dx < 2; ++dx)
            for (int dy = 0; dy < 2; ++dy) keys.push_back(cell_key(c - glm::ivec2(dx, dy)));
    }
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    for (uint64_t k : keys) tiles_.push_back({int32_t(uint32_t(k >> 32)), int32_t(uint32_t(k))});
}

glm::dvec2 SceneTiling::centre(size_t k) const { return (glm::dvec2(tiles_[k]) + 1.0) * (0.5 * tile_); }

std::vector<uint32_t> SceneTiling::members(size_t k) const {
    std::vector<uint32_t> out;
    for (int dx = 0; dx < 2; ++dx)
        for (int dy = 0; dy < 2; ++dy) {
            const auto it = cells_.find(cell_key(tiles_[k] + glm::ivec2(dx, dy)));
            if (it != cells_.end()) out.insert(out.end(), it->second.begin(), it->second.end());
        }
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace pg::data::semantic

#pragma once
// A uniform hash grid over a subset of points, for radius and nearest-neighbour queries.
// Cells are keyed by their integer coordinates packed into 64 bits (21 bits per axis,
// wrapping): two far-apart cells may share a key, which only adds points that the exact
// distance test then rejects, so queries stay exact for any extent.
#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

#include <glm/glm.hpp>

namespace pg::data::clicks {

class PointGrid {
public:
    // Indexes positions[i] for every i in `members`; cell > 0. Keeps a view of positions.
    PointGrid(std::span<const glm::vec3> positions, std::span<const uint32_t> members, float cell);

    float cell() const { return cell_; }
    glm::ivec3 cell_of(glm::vec3 p) const;
    // The indices in one cell (empty span if none), in ascending index order.
    std::span<const uint32_t> points_in(glm::ivec3 c) const;
    // The occupied cells, each once, in ascending key order (deterministic).
    const std::vector<glm::ivec3>& cells() const { return cell_list_; }

    // Nearest indexed point to p other than `exclude`, searching at most `max_rings` rings
    // of cells around p's cell; returns the squared distance (or -1 if none found) and
    // writes the index. Ties keep the lowest index.
    double nearest(glm::vec3 p, uint32_t exclude, int max_rings, uint32_t* index) const;

private:
    static uint64_t key(glm::ivec3 c);

    std::span<const glm::vec3> positions_;
    float cell_;
    glm::vec3 origin_;
    std::vector<uint32_t> sorted_;  // member indices grouped by cell
    std::unordered_map<uint64_t, std::pair<uint32_t, uint32_t>> ranges_;  // key -> [begin, end) in sorted_
    std::vector<glm::ivec3> cell_list_;
};

// Median distance from a point to its nearest neighbour, over an evenly strided sample of
// at most 4096 points; coincident duplicates (distance 0) and points with no neighbour
// within a few cells (far outliers) are left out. 0 if nothing is left.
float median_spacing(std::span<const glm::vec3> positions);

}  // namespace pg::data::clicks

#pragma once
// A k-d tree over a set of points for exact nearest-distance queries at any range: the
// dense grids elsewhere answer "how far, roughly", this answers "how far, exactly" even
// when the nearest point is hundreds of cells away (a sparse neighbourhood).
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace pg::data::clicks {

class KdTree {
public:
    // Indexes positions[i] for every i in `members` (copied, so positions may go away). Leaves
    // of up to `leaf` points: larger ones build faster and answer each query slower (for a few
    // queries over many points, a few hundred pays).
    KdTree(std::span<const glm::vec3> positions, std::span<const uint32_t> members, uint32_t leaf = 12);

    bool empty() const { return points_.empty(); }
    // min(bound2, squared distance from p to the nearest indexed point). A tight bound
    // (e.g. the largest distance that matters) makes the query cheaper.
    double nearest2(glm::dvec3 p, double bound2) const;

private:
    struct Node {
        float split = 0;
        int32_t axis = -1;       // -1: leaf holding points_[begin, end)
        uint32_t begin = 0, end = 0;
        uint32_t left = 0, right = 0;
    };
    uint32_t build(uint32_t begin, uint32_t end);

    std::vector<glm::vec3> points_;
    std::vector<Node> nodes_;
    uint32_t leaf_;
};

}  // namespace pg::data::clicks

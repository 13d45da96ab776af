#include "dataset/clicks/kd_tree.h"

#include <algorithm>

namespace pg::data::clicks {

KdTree::KdTree(std::span<const glm::vec3> positions, std::span<const uint32_t> members, uint32_t leaf)
    : leaf_(std::max(leaf, 1u)) {
    points_.reserve(members.size());
    for (uint32_t i : members) points_.push_back(positions[i]);
    if (!points_.empty()) {
        nodes_.reserve(2 * (points_.size() / leaf_ + 1));
        build(0, uint32_t(points_.size()));
    }
}

uint32_t KdTree::build(uint32_t begin, uint32_t end) {
    const uint32_t id = uint32_t(nodes_.size());
    nodes_.push_back(Node{0, -1, begin, end, 0, 0});
    if (end - begin <= leaf_) return id;
    glm::vec3 lo = points_[begin], hi = lo;
    for (uint32_t i = begin; i < end; ++i) {
        lo = glm::min(lo, points_[i]);
        hi = glm::max(hi, points_[i]);
    }
    const glm::vec3 ext = hi - lo;
    const int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : ext.y >= ext.z ? 1 : 2;
    if (!(ext[axis] > 0)) return id;  // all coincident: one leaf
    // Median split: left holds coordinates <= split, right >= split.
    const uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(points_.begin() + begin, points_.begin() + mid, points_.begin() + end,
                     [axis](const glm::vec3& a, const glm::vec3& b) { return a[axis] < b[axis]; });
    const float split = points_[mid][axis];  // read before the children reorder their ranges
    const uint32_t left = build(begin, mid);
    const uint32_t right = build(mid, end);
    Node& n = nodes_[id];
    n.split = split;
    n.axis = axis;
    n.left = left;
    n.right = right;
    return id;
}

double KdTree::nearest2(glm::dvec3 p, double bound2) const {
    if (nodes_.empty()) return bound2;
    double best = bound2;
    // Depth-first, nearer child first; a far child is visited only if the splitting plane
    // is closer than the best distance so far.
    struct Pending {
        uint32_t node;
        double plane2;
    };
    Pending stack[128];
    int top = 0;
    stack[top++] = {0, 0.0};
    while (top > 0) {
        const Pending cur = stack[--top];
        if (cur.plane2 >= best) continue;
        const Node& n = nodes_[cur.node];
        if (n.axis < 0) {
            for (uint32_t i = n.begin; i < n.end; ++i) {
                const glm::dvec3 d = glm::dvec3(points_[i]) - p;
                best = std::min(best, glm::dot(d, d));
            }
            continue;
        }
        const double diff = p[n.axis] - double(n.split);
        const uint32_t near = diff < 0 ? n.left : n.right, far = diff < 0 ? n.right : n.left;
        stack[top++] = {far, std::max(cur.plane2, diff * diff)};
        stack[top++] = {near, cur.plane2};
    }
    return best;
}

}  // namespace pg::data::clicks

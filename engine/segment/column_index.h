#pragma once
// Gaussians binned by where they lie across the up axis. An ROI column (a rectangle across up,
// unbounded along it) then costs what it holds, not what the scene holds: a click in a
// 6 M-Gaussian scene looks at the few hundred thousand Gaussians near it.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "dataset/gaussian_cloud.h"

namespace pg::seg {

class ColumnIndex {
public:
    // Bins the cloud's centres by their coordinates along `a` and `b` (two axes across up).
    ColumnIndex(const data::GaussianCloud& cloud, const glm::dvec3& a, const glm::dvec3& b);

    // Every Gaussian whose centre c has |(c - centre) . a| <= half_a and |(c - centre) . b| <= half_b,
    // and some near it (whole cells, and a margin for float rounding): a superset, ascending, or
    // cell by cell where the caller's order does not matter (`sorted` false: no sort of them all).
    std::vector<uint32_t> candidates(const glm::dvec3& centre, double half_a, double half_b, bool sorted = true) const;

    bool has_axes(const glm::dvec3& a, const glm::dvec3& b) const { return a == a_ && b == b_; }
    size_t size() const { return ids_.size(); }

private:
    glm::dvec3 a_, b_;
    glm::dvec2 lo_{0.0};
    double cell_ = 1.0;
    uint32_t nx_ = 1, ny_ = 1;
    std::vector<uint32_t> start_;  // per cell, where its ids begin in ids_ (nx * ny + 1 entries)
    std::vector<uint32_t> ids_;    // Gaussian ids, cell by cell, ascending within a cell
};

}  // namespace pg::seg

#include "engine/segment/column_index.h"

#include <algorithm>
#include <cmath>

namespace pg::seg {

namespace {

// About this many Gaussians per cell on average: a column's query touches few cells, and the
// cell table stays small beside the ids.
constexpr double kPerCell = 16.0;
constexpr uint32_t kMaxSide = 4096;

}  // namespace

ColumnIndex::ColumnIndex(const data::GaussianCloud& cloud, const glm::dvec3& a, const glm::dvec3& b) : a_(a), b_(b) {
    const size_t n = cloud.size();
    std::vector<glm::dvec2> uv(n);
    for (size_t i = 0; i < n; ++i) {
        const glm::dvec3 p(cloud.mean[i]);
        uv[i] = glm::dvec2(glm::dot(p, a), glm::dot(p, b));
        if (!std::isfinite(uv[i].x) || !std::isfinite(uv[i].y)) uv[i] = glm::dvec2(0.0);
    }
    // The grid spans the bulk of the scene (0.5 % to 99.5 % along each axis): a capture's far
    // floaters and sky would otherwise stretch it until its core fills a few cells. What lies
    // past it is binned into the border cells, which every query reaching past the grid takes.
    glm::dvec2 hi(0.0);
    if (n > 0) {
        std::vector<double> q(n);
        for (int axis = 0; axis < 2; ++axis) {
            for (size_t i = 0; i < n; ++i) q[i] = uv[i][axis];
            const size_t k0 = n / 200, k1 = n - 1 - n / 200;
            std::nth_element(q.begin(), q.begin() + long(k0), q.end());
            lo_[axis] = q[k0];
            std::nth_element(q.begin(), q.begin() + long(k1), q.end());
            hi[axis] = q[k1];
        }
    }
    const glm::dvec2 extent = glm::max(hi - lo_, glm::dvec2(1e-9));
    cell_ = std::max(std::sqrt(extent.x * extent.y * kPerCell / double(std::max<size_t>(n, 1))), 1e-9);
    cell_ = std::max({cell_, extent.x / kMaxSide, extent.y / kMaxSide});
    nx_ = uint32_t(std::min<double>(kMaxSide, std::floor(extent.x / cell_) + 1));
    ny_ = uint32_t(std::min<double>(kMaxSide, std::floor(extent.y / cell_) + 1));
    auto cell_of = [&](const glm::dvec2& q) {
        const uint32_t x = uint32_t(std::clamp((q.x - lo_.x) / cell_, 0.0, double(nx_ - 1)));
        const uint32_t y = uint32_t(std::clamp((q.y - lo_.y) / cell_, 0.0, double(ny_ - 1)));
        return size_t(y) * nx_ + x;
    };
    // A counting sort by cell, in id order, so each cell's ids ascend.
    start_.assign(size_t(nx_) * ny_ + 1, 0);
    for (size_t i = 0; i < n; ++i) ++start_[cell_of(uv[i]) + 1];
    for (size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    ids_.resize(n);
    std::vector<uint32_t> fill(start_.begin(), start_.end() - 1);
    for (size_t i = 0; i < n; ++i) ids_[fill[cell_of(uv[i])]++] = uint32_t(i);
}

std::vector<uint32_t> ColumnIndex::candidates(const glm::dvec3& centre, double half_a, double half_b, bool sorted) const {
    // Widened well past float rounding: the exact test (on the GPU in float, or on the host in
    // double) comes after, on these candidates.
    const glm::dvec2 c(glm::dot(centre, a_), glm::dot(centre, b_));
    const double slack = 1e-4 * (std::abs(c.x) + std::abs(c.y) + half_a + half_b) + 1e-6;
    const double x0 = (c.x - half_a - slack - lo_.x) / cell_, x1 = (c.x + half_a + slack - lo_.x) / cell_;
    const double y0 = (c.y - half_b - slack - lo_.y) / cell_, y1 = (c.y + half_b + slack - lo_.y) / cell_;
    std::vector<uint32_t> out;
    if (!(x0 <= x1 && y0 <= y1)) return out;  // NaN
    const uint32_t cx0 = uint32_t(std::clamp(std::floor(x0), 0.0, double(nx_ - 1)));
    const uint32_t cx1 = uint32_t(std::clamp(std::floor(x1), 0.0, double(nx_ - 1)));
    const uint32_t cy0 = uint32_t(std::clamp(std::floor(y0), 0.0, double(ny_ - 1)));
    const uint32_t cy1 = uint32_t(std::clamp(std::floor(y1), 0.0, double(ny_ - 1)));
    for (uint32_t y = cy0; y <= cy1; ++y) {
        const size_t row = size_t(y) * nx_;
        out.insert(out.end(), ids_.begin() + start_[row + cx0], ids_.begin() + start_[row + cx1 + 1]);
    }
    if (sorted) std::sort(out.begin(), out.end());
    return out;
}

}  // namespace pg::seg

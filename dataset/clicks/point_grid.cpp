#include "dataset/clicks/point_grid.h"

#include <algorithm>
#include <cmath>

namespace pg::data::clicks {

uint64_t PointGrid::key(glm::ivec3 c) {
    constexpr uint64_t kMask = (1u << 21) - 1;
    return (uint64_t(uint32_t(c.x)) & kMask) | ((uint64_t(uint32_t(c.y)) & kMask) << 21) |
           ((uint64_t(uint32_t(c.z)) & kMask) << 42);
}

glm::ivec3 PointGrid::cell_of(glm::vec3 p) const {
    // Clamped so that far points cannot overflow the conversion; clamped cells still hold
    // exact positions, and every query checks true distances.
    const glm::dvec3 c = glm::floor(glm::dvec3(p - origin_) / double(cell_));
    const glm::dvec3 lim(1e9);
    return glm::ivec3(glm::clamp(c, -lim, lim));
}

PointGrid::PointGrid(std::span<const glm::vec3> positions, std::span<const uint32_t> members, float cell)
    : positions_(positions), cell_(cell), origin_(0.0f) {
    if (!members.empty()) origin_ = positions[members[0]];
    std::vector<std::pair<uint64_t, uint32_t>> keyed;
    keyed.reserve(members.size());
    for (uint32_t i : members) keyed.emplace_back(key(cell_of(positions[i])), i);
    std::sort(keyed.begin(), keyed.end());
    sorted_.resize(keyed.size());
    ranges_.reserve(keyed.size() / 2 + 1);
    for (size_t b = 0; b < keyed.size();) {
        size_t e = b;
        while (e < keyed.size() && keyed[e].first == keyed[b].first) {
            sorted_[e] = keyed[e].second;
            ++e;
        }
        ranges_.emplace(keyed[b].first, std::pair<uint32_t, uint32_t>(uint32_t(b), uint32_t(e)));
        cell_list_.push_back(cell_of(positions[keyed[b].second]));
        b = e;
    }
}

std::span<const uint32_t> PointGrid::points_in(glm::ivec3 c) const {
    auto it = ranges_.find(key(c));
    if (it == ranges_.end()) return {};
    return std::span<const uint32_t>(sorted_.data() + it->second.first, it->second.second - it->second.first);
}

double PointGrid::nearest(glm::vec3 p, uint32_t exclude, int max_rings, uint32_t* index) const {
    const glm::ivec3 c = cell_of(p);
    const glm::dvec3 pd(p);
    double best = -1;
    for (int k = 0; k <= max_rings; ++k) {
        // Every point in ring k is at least (k - 1) cells away along some axis.
        if (best >= 0 && k >= 1 && double(k - 1) * cell_ * (k - 1) * cell_ >= best) break;
        if (k >= 2 && double(2 * k + 1) * (2 * k + 1) * (2 * k + 1) > 4.0 * double(cell_list_.size())) {
            // The rings left hold more cells than are occupied (a query far from every point,
            // or the points bunched in a few cells): every indexed point within max_rings
            // instead, the same answer without visiting millions of empty cells.
            for (uint32_t j : sorted_) {
                const glm::ivec3 off = glm::abs(cell_of(positions_[j]) - c);
                if (j == exclude || std::max(off.x, std::max(off.y, off.z)) > max_rings) continue;
                const glm::dvec3 d = glm::dvec3(positions_[j]) - pd;
                const double d2 = glm::dot(d, d);
                if (best < 0 || d2 < best || (d2 == best && j < *index)) best = d2, *index = j;
            }
            return best;
        }
        for (int dz = -k; dz <= k; ++dz)
            for (int dy = -k; dy <= k; ++dy) {
                const bool face = std::abs(dz) == k || std::abs(dy) == k;
                for (int dx = -k; dx <= k; dx += face ? 1 : 2 * k) {
                    for (uint32_t j : points_in(c + glm::ivec3(dx, dy, dz))) {
                        if (j == exclude) continue;
                        const glm::dvec3 d = glm::dvec3(positions_[j]) - pd;
                        const double d2 = glm::dot(d, d);
                        if (best < 0 || d2 < best || (d2 == best && j < *index)) {
                            best = d2;
                            *index = j;
                            // A point at p itself is in p's cell, which lists its points in index
                            // order: the first found is the answer (and thousands of Gaussians
                            // collapsed onto one point cost one look each, not a scan each).
                            if (d2 == 0) return 0;
                        }
                    }
                    if (k == 0) break;
                }
            }
    }
    return best;
}

float median_spacing(std::span<const glm::vec3> positions) {
    const size_t n = positions.size();
    if (n < 2) return 0;
    // Cell size from the robust extent (1st..99th percentile per axis), so a few floaters
    // do not make the cells huge: about one point per cell for a volume, more on surfaces.
    float side = 0;
    for (int a = 0; a < 3; ++a) {
        std::vector<float> v(n);
        for (size_t i = 0; i < n; ++i) v[i] = positions[i][a];
        const size_t lo = n / 100, hi = n - 1 - n / 100;
        std::nth_element(v.begin(), v.begin() + lo, v.end());
        const float vlo = v[lo];
        std::nth_element(v.begin(), v.begin() + hi, v.end());
        side = std::max(side, v[hi] - vlo);
    }
    if (!(side > 0)) return 0;
    std::vector<uint32_t> all(n);
    for (size_t i = 0; i < n; ++i) all[i] = uint32_t(i);
    const PointGrid grid(positions, all, side / std::cbrt(float(n)));

    const size_t samples = std::min<size_t>(n, 4096);
    std::vector<double> d;
    d.reserve(samples);
    for (size_t s = 0; s < samples; ++s) {
        const uint32_t i = uint32_t(s * n / samples);
        uint32_t j = 0;
        const double d2 = grid.nearest(positions[i], i, 4, &j);
        if (d2 > 0) d.push_back(std::sqrt(d2));
    }
    if (d.empty()) return 0;
    std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
    return float(d[d.size() / 2]);
}

}  // namespace pg::data::clicks

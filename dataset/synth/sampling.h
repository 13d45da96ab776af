#pragma once
// Small helpers for area-proportional surface sampling.
#include <algorithm>
#include <vector>

#include "dataset/synth/geometry.h"

namespace pg::data::synth {

// Picks an index with probability proportional to its area.
class AreaTable {
public:
    void push(double area) { cumulative_.push_back(total() + std::max(0.0, area)); }
    double total() const { return cumulative_.empty() ? 0.0 : cumulative_.back(); }
    size_t size() const { return cumulative_.size(); }
    size_t pick(Rng& rng) const {
        const double x = rng.uniform() * total();
        const auto it = std::upper_bound(cumulative_.begin(), cumulative_.end(), x);
        return std::min(size_t(it - cumulative_.begin()), cumulative_.size() - 1);
    }

private:
    std::vector<double> cumulative_;
};

// Triangle areas of the fan (v0, v[k+1], v[k+2]) of a convex polygon.
inline AreaTable fan_areas(const std::vector<glm::dvec3>& v) {
    AreaTable t;
    for (size_t k = 0; k + 2 < v.size(); ++k) t.push(0.5 * glm::length(glm::cross(v[k + 1] - v[0], v[k + 2] - v[0])));
    return t;
}

inline glm::dvec3 uniform_in_triangle(Rng& rng, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    double u = rng.uniform(), v = rng.uniform();
    if (u + v > 1.0) {
        u = 1.0 - u;
        v = 1.0 - v;
    }
    return a + u * (b - a) + v * (c - a);
}

inline glm::dvec3 uniform_on_sphere(Rng& rng) {
    const double z = rng.uniform(-1.0, 1.0), a = 2.0 * kPi * rng.uniform();
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    return {r * std::cos(a), r * std::sin(a), z};
}

// Distance from p to the infinite line through a and b.
inline double distance_to_line(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
    const glm::dvec3 d = b - a;
    const double len = glm::length(d);
    if (len == 0.0) return glm::length(p - a);
    return glm::length(glm::cross(p - a, d)) / len;
}

}  // namespace pg::data::synth

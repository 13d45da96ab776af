#include "dataset/up_axis.h"

#include <algorithm>
#include <cmath>

#include "dataset/error.h"
#include "dataset/random.h"

namespace pg::data {

glm::dvec3 up_from_cameras(const std::vector<Camera>& cameras) {
    if (cameras.empty()) throw InputError("--cameras", "no cameras to take the up axis from (give --up)");
    glm::dvec3 sum(0.0);
    for (const auto& c : cameras) sum += c.up();
    double len = glm::length(sum);
    if (!(len > 0.3 * double(cameras.size())))
        throw InputError("--cameras", "the cameras' up directions disagree; give --up or --up ground");
    return sum / len;
}

glm::dvec3 up_from_ground_plane(const GaussianCloud& cloud, uint64_t seed) {
    const size_t n = cloud.size();
    if (n < 3) throw InputError("scene", "too few Gaussians to fit a ground plane");
    // A sample keeps each RANSAC round cheap on multi-million Gaussian scenes.
    std::vector<glm::dvec3> pts;
    const size_t stride = std::max<size_t>(1, n / 20000);
    for (size_t i = 0; i < n; i += stride) pts.push_back(glm::dvec3(cloud.mean[i]));
    glm::dvec3 lo = pts[0], hi = pts[0];
    for (auto& p : pts) lo = glm::min(lo, p), hi = glm::max(hi, p);
    const double tolerance = 0.01 * glm::length(hi - lo);

    Rng rng(seed);
    glm::dvec3 best_n(0, 0, 1);
    glm::dvec3 best_p(0.0);
    size_t best_count = 0;
    for (int round = 0; round < 400; ++round) {
        const auto& a = pts[rng.next() % pts.size()];
        const auto& b = pts[rng.next() % pts.size()];
        const auto& c = pts[rng.next() % pts.size()];
        glm::dvec3 normal = glm::cross(b - a, c - a);
        double len = glm::length(normal);
        if (!(len > 1e-12)) continue;
        normal /= len;
        size_t count = 0;
        for (auto& p : pts) count += std::abs(glm::dot(p - a, normal)) <= tolerance;
        if (count > best_count) best_count = count, best_n = normal, best_p = a;
    }
    // Most of the scene stands on the ground: up points to the side holding more Gaussians.
    size_t above = 0, below = 0;
    for (auto& p : pts) {
        double d = glm::dot(p - best_p, best_n);
        above += d > tolerance;
        below += d < -tolerance;
    }
    return above >= below ? best_n : -best_n;
}

void horizontal_axes(glm::dvec3 up, glm::dvec3& length_axis, glm::dvec3& width_axis) {
    up = glm::normalize(up);
    // The world axis least aligned with up seeds the frame.
    glm::dvec3 e(1, 0, 0);
    if (std::abs(up.y) < std::abs(up.x) && std::abs(up.y) <= std::abs(up.z)) e = glm::dvec3(0, 1, 0);
    else if (std::abs(up.z) < std::abs(up.x) && std::abs(up.z) < std::abs(up.y)) e = glm::dvec3(0, 0, 1);
    length_axis = glm::normalize(e - glm::dot(e, up) * up);
    width_axis = glm::cross(up, length_axis);
}

}  // namespace pg::data

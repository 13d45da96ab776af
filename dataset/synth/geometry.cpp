#include "dataset/synth/geometry.h"

#include <cmath>

namespace pg::data::synth {

bool ray_box(const Ray& ray, const glm::dvec3& inv_dir, const Aabb& box, double& t0, double& t1) {
    double lo = -kInf, hi = kInf;
    for (int a = 0; a < 3; ++a) {
        if (ray.dir[a] == 0.0) {
            if (ray.origin[a] < box.lo[a] || ray.origin[a] > box.hi[a]) return false;
            continue;
        }
        double ta = (box.lo[a] - ray.origin[a]) * inv_dir[a], tb = (box.hi[a] - ray.origin[a]) * inv_dir[a];
        if (ta > tb) std::swap(ta, tb);
        lo = std::max(lo, ta);
        hi = std::min(hi, tb);
    }
    t0 = lo;
    t1 = hi;
    return lo <= hi;
}

Frame Frame::rotation(const glm::dvec3& axis, double angle) {
    const glm::dvec3 k = glm::normalize(axis);
    const double c = std::cos(angle), s = std::sin(angle);
    // Rodrigues: R = c I + s [k]x + (1 - c) k k^T, column-major.
    glm::dmat3 R(c);
    R += (1.0 - c) * glm::outerProduct(k, k);
    R[1][0] += -s * k.z;
    R[2][0] += s * k.y;
    R[0][1] += s * k.z;
    R[2][1] += -s * k.x;
    R[0][2] += -s * k.y;
    R[1][2] += s * k.x;
    return Frame{R, glm::dvec3(0.0)};
}

glm::dvec3 perpendicular(const glm::dvec3& n) {
    const glm::dvec3 a = std::abs(n.x) < 0.8 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    return glm::normalize(glm::cross(n, a));
}

Frame Frame::axes(const glm::dvec3& z, const glm::dvec3& x_hint, const glm::dvec3& o) {
    const glm::dvec3 zz = glm::normalize(z);
    glm::dvec3 x = x_hint - zz * glm::dot(zz, x_hint);
    x = glm::length(x) < 1e-9 ? perpendicular(zz) : glm::normalize(x);
    return Frame{glm::dmat3(x, glm::cross(zz, x), zz), o};
}

Frame operator*(const Frame& a, const Frame& b) { return Frame{a.R * b.R, a.R * b.origin + a.origin}; }

Aabb transform_box(const Frame& f, const Aabb& b) {
    Aabb out;
    for (int i = 0; i < 8; ++i)
        out.grow(f.to_world(glm::dvec3(i & 1 ? b.hi.x : b.lo.x, i & 2 ? b.hi.y : b.lo.y, i & 4 ? b.hi.z : b.lo.z)));
    return out;
}

}  // namespace pg::data::synth

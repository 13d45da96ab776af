// Convex polyhedra: slab-style ray clipping against every half-space, faces found by
// clipping a large square in each plane by all the others.
#include <cmath>

#include "dataset/synth/primitives.h"
#include "dataset/synth/sampling.h"

namespace pg::data::synth {
namespace {

class Convex final : public Primitive {
public:
    explicit Convex(std::vector<HalfSpace> planes) : planes_(std::move(planes)) {
        for (auto& h : planes_) {
            const double len = glm::length(h.n);
            h.n /= len;
            h.d /= len;
        }
        double extent = 1.0;
        for (const auto& h : planes_) extent = std::max(extent, 4.0 * std::abs(h.d));
        for (size_t i = 0; i < planes_.size(); ++i) {
            Face f;
            f.n = planes_[i].n;
            f.verts = clip_face(i, 100.0 * extent);
            if (f.verts.size() < 3) continue;
            f.triangles = fan_areas(f.verts);
            f.area = f.triangles.total();
            if (f.area <= 0.0) continue;
            f.tangent = std::abs(f.n.z) < 0.9 ? glm::normalize(glm::dvec3(-f.n.y, f.n.x, 0.0))
                                              : glm::normalize(glm::dvec3(1, 0, 0) - f.n * f.n.x);
            for (const auto& v : f.verts) box_.grow(v);
            faces_.push_back(std::move(f));
        }
        for (const auto& f : faces_) face_areas_.push(f.area);
    }

    bool intersect(const Ray& r, double t_min, double t_max, double& t) const override {
        double enter = -kInf, exit = kInf;
        for (const auto& h : planes_) {
            const double dn = glm::dot(h.n, r.dir), dist = h.d - glm::dot(h.n, r.origin);
            if (dn == 0.0) {
                if (dist < 0.0) return false;
                continue;
            }
            const double th = dist / dn;
            if (dn < 0.0) enter = std::max(enter, th);
            else exit = std::min(exit, th);
            if (enter > exit) return false;
        }
        const double hit = enter > t_min ? enter : exit;
        if (hit <= t_min || hit >= t_max) return false;
        t = hit;
        return true;
    }

    bool contains(const glm::dvec3& p) const override {
        for (const auto& h : planes_)
            if (glm::dot(h.n, p) > h.d) return false;
        return true;
    }

    double area() const override { return face_areas_.total(); }
    Aabb bounds() const override { return box_; }

    SurfacePoint sample(Rng& rng) const override {
        const Face& f = faces_[face_areas_.pick(rng)];
        const size_t k = f.triangles.pick(rng);
        SurfacePoint s;
        s.p = uniform_in_triangle(rng, f.verts[0], f.verts[k + 1], f.verts[k + 2]);
        s.n = f.n;
        s.tangent = f.tangent;
        s.feature = kInf;
        for (size_t i = 0; i < f.verts.size(); ++i) {
            const glm::dvec3 a = f.verts[i], b = f.verts[(i + 1) % f.verts.size()];
            s.feature = std::min(s.feature, distance_to_line(s.p, a, b));
        }
        return s;
    }

private:
    struct Face {
        glm::dvec3 n{0.0}, tangent{0.0};
        std::vector<glm::dvec3> verts;  // convex, in order
        AreaTable triangles;            // fan (0, k+1, k+2)
        double area = 0.0;
    };

    // The polygon of plane i inside every other half-space (Sutherland-Hodgman).
    std::vector<glm::dvec3> clip_face(size_t i, double size) const {
        const HalfSpace& h = planes_[i];
        const glm::dvec3 u = perpendicular(h.n), v = glm::cross(h.n, u), c = h.n * h.d;
        std::vector<glm::dvec3> poly = {c - size * u - size * v, c + size * u - size * v, c + size * u + size * v,
                                        c - size * u + size * v};
        for (size_t j = 0; j < planes_.size() && poly.size() >= 3; ++j) {
            if (j == i) continue;
            const HalfSpace& g = planes_[j];
            std::vector<glm::dvec3> out;
            for (size_t k = 0; k < poly.size(); ++k) {
                const glm::dvec3 a = poly[k], b = poly[(k + 1) % poly.size()];
                const double da = glm::dot(g.n, a) - g.d, db = glm::dot(g.n, b) - g.d;
                if (da <= 0.0) out.push_back(a);
                if ((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0)) out.push_back(a + (b - a) * (da / (da - db)));
            }
            poly = std::move(out);
        }
        return poly;
    }

    std::vector<HalfSpace> planes_;
    std::vector<Face> faces_;
    AreaTable face_areas_;
    Aabb box_;
};

}  // namespace

PrimitivePtr make_convex(const std::vector<HalfSpace>& planes) { return std::make_shared<Convex>(planes); }

PrimitivePtr make_box(const glm::dvec3& h) {
    return make_convex({{{1, 0, 0}, h.x}, {{-1, 0, 0}, h.x}, {{0, 1, 0}, h.y},
                        {{0, -1, 0}, h.y}, {{0, 0, 1}, h.z}, {{0, 0, -1}, h.z}});
}

PrimitivePtr make_prism(const std::vector<glm::dvec2>& polygon, double z0, double z1) {
    std::vector<HalfSpace> planes = {{{0, 0, 1}, z1}, {{0, 0, -1}, -z0}};
    for (size_t i = 0; i < polygon.size(); ++i) {
        const glm::dvec2 a = polygon[i], b = polygon[(i + 1) % polygon.size()];
        const glm::dvec3 n(b.y - a.y, a.x - b.x, 0.0);  // outward for counter-clockwise order
        planes.push_back({n, glm::dot(n, glm::dvec3(a, 0.0))});
    }
    return make_convex(planes);
}

PrimitivePtr make_tapered_box(glm::dvec2 bh, glm::dvec2 th, double height, glm::dvec2 shift) {
    std::vector<HalfSpace> planes = {{{0, 0, 1}, height}, {{0, 0, -1}, 0.0}};
    for (int axis = 0; axis < 2; ++axis)
        for (double s : {1.0, -1.0}) {
            // The side through the bottom edge at s*bh and the top edge at shift + s*th.
            const double x0 = s * bh[axis], x1 = shift[axis] + s * th[axis];
            glm::dvec3 n(0.0);
            n[axis] = s * height;
            n.z = s * (x0 - x1);
            glm::dvec3 p(0.0);
            p[axis] = x0;
            planes.push_back({n, glm::dot(n, p)});
        }
    return make_convex(planes);
}

PrimitivePtr make_gable_roof(double length, double width, double height) {
    const double w = width / 2;
    return make_convex({{{0, 0, -1}, 0.0},
                        {{1, 0, 0}, length / 2},
                        {{-1, 0, 0}, length / 2},
                        {{0, height, w}, w * height},
                        {{0, -height, w}, w * height}});
}

PrimitivePtr make_hip_roof(double length, double width, double height, double ridge) {
    const double w = width / 2, l = length / 2, r = std::min(ridge, length) / 2;
    const double run = std::max(l - r, 1e-6);
    return make_convex({{{0, 0, -1}, 0.0},
                        {{0, height, w}, w * height},
                        {{0, -height, w}, w * height},
                        {{height, 0, run}, l * height},
                        {{-height, 0, run}, l * height}});
}

}  // namespace pg::data::synth

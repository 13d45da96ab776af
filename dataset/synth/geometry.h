#pragma once
// Geometry shared by the analytic shapes: rays, boxes, rigid frames, and the interface every
// primitive implements (exact first hit for ground-truth masks, inside test for hiding
// surfaces that touch, area-proportional surface sampling for Gaussians).
#include <algorithm>
#include <limits>

#include <glm/glm.hpp>

#include "dataset/synth/random.h"

namespace pg::data::synth {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();

struct Ray {
    glm::dvec3 origin{0.0};
    glm::dvec3 dir{0.0, 0.0, 1.0};  // need not be unit; t is in units of |dir|
};

struct Aabb {
    glm::dvec3 lo{kInf}, hi{-kInf};
    void grow(const glm::dvec3& p) { lo = glm::min(lo, p); hi = glm::max(hi, p); }
    void grow(const Aabb& b) { lo = glm::min(lo, b.lo); hi = glm::max(hi, b.hi); }
    bool empty() const { return lo.x > hi.x; }
    bool contains(const glm::dvec3& p) const {
        return p.x >= lo.x && p.y >= lo.y && p.z >= lo.z && p.x <= hi.x && p.y <= hi.y && p.z <= hi.z;
    }
    glm::dvec3 centre() const { return 0.5 * (lo + hi); }
    glm::dvec3 size() const { return hi - lo; }
};

// Parameter interval [t0, t1] of a ray inside a box; false if it misses.
bool ray_box(const Ray& ray, const glm::dvec3& inv_dir, const Aabb& box, double& t0, double& t1);

// Rigid transform from a shape's local coordinates to its parent: x = R * local + origin.
struct Frame {
    glm::dmat3 R{1.0};
    glm::dvec3 origin{0.0};

    glm::dvec3 to_world(const glm::dvec3& p) const { return R * p + origin; }
    glm::dvec3 dir_to_world(const glm::dvec3& d) const { return R * d; }
    glm::dvec3 to_local(const glm::dvec3& p) const { return glm::transpose(R) * (p - origin); }
    glm::dvec3 dir_to_local(const glm::dvec3& d) const { return glm::transpose(R) * d; }
    Ray to_local(const Ray& r) const { return {to_local(r.origin), dir_to_local(r.dir)}; }

    static Frame at(const glm::dvec3& o) { return Frame{glm::dmat3(1.0), o}; }
    // Rotation about an axis through the origin (right-handed, radians).
    static Frame rotation(const glm::dvec3& axis, double angle);
    // Local x, y, z axes given in the parent (orthonormalised from z and a hint for x).
    static Frame axes(const glm::dvec3& z, const glm::dvec3& x_hint, const glm::dvec3& o);
};

// a * b: first b, then a.
Frame operator*(const Frame& a, const Frame& b);
Aabb transform_box(const Frame& f, const Aabb& b);

// A point on a surface with its outward normal, a tangent (the direction a Gaussian's long
// axis prefers: grain, edges, rims) and the local feature size (distance to the nearest
// edge or radius of curvature) that bounds the Gaussians there.
struct SurfacePoint {
    glm::dvec3 p{0.0}, n{0.0, 0.0, 1.0}, tangent{1.0, 0.0, 0.0};
    double feature = kInf;
};

class Primitive {
public:
    virtual ~Primitive() = default;
    // First crossing of the surface with t in (t_min, t_max), for a ray starting outside
    // the solid; writes t and returns true if there is one.
    virtual bool intersect(const Ray& ray, double t_min, double t_max, double& t) const = 0;
    // Whether p is inside the solid (boundary points may go either way).
    virtual bool contains(const glm::dvec3& p) const = 0;
    virtual double area() const = 0;
    // A point uniformly distributed over the surface area.
    virtual SurfacePoint sample(Rng& rng) const = 0;
    virtual Aabb bounds() const = 0;
};

// Any unit vector perpendicular to n.
glm::dvec3 perpendicular(const glm::dvec3& n);

}  // namespace pg::data::synth

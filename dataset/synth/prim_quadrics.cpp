// Solids bounded by quadrics: ellipsoids (optionally cut flat), cylinders and tubes,
// frustums and capsules. Hits are the nearest valid root over the solid's surface patches.
#include <cmath>

#include "dataset/synth/primitives.h"
#include "dataset/synth/sampling.h"

namespace pg::data::synth {

int solve_quadratic(double a, double b, double c, double& t0, double& t1) {
    if (a == 0.0) {
        if (b == 0.0) return 0;
        t0 = t1 = -c / b;
        return 1;
    }
    const double disc = b * b - 4.0 * a * c;
    if (disc < 0.0) return 0;
    const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
    if (q == 0.0) {
        t0 = t1 = 0.0;
        return 1;
    }
    t0 = q / a;
    t1 = c / q;
    if (t0 > t1) std::swap(t0, t1);
    return 2;
}

namespace {

// Keeps the smallest candidate in (t_min, best).
struct Nearest {
    double t_min, best;
    void offer(double t) {
        if (t > t_min && t < best) best = t;
    }
};

// Roots of the infinite cylinder x^2 + y^2 = r^2.
int cylinder_roots(const Ray& r, double radius, double& t0, double& t1) {
    const double a = r.dir.x * r.dir.x + r.dir.y * r.dir.y;
    const double b = 2.0 * (r.origin.x * r.dir.x + r.origin.y * r.dir.y);
    const double c = r.origin.x * r.origin.x + r.origin.y * r.origin.y - radius * radius;
    return a == 0.0 ? 0 : solve_quadratic(a, b, c, t0, t1);
}

int sphere_roots(const Ray& r, const glm::dvec3& centre, double radius, double& t0, double& t1) {
    const glm::dvec3 o = r.origin - centre;
    return solve_quadratic(glm::dot(r.dir, r.dir), 2.0 * glm::dot(o, r.dir), glm::dot(o, o) - radius * radius, t0, t1);
}

// The plane z = z0 crossed at a radius in [rho_lo, rho_hi].
void offer_disc(Nearest& near, const Ray& r, double z0, double rho_lo, double rho_hi) {
    if (r.dir.z == 0.0) return;
    const double t = (z0 - r.origin.z) / r.dir.z;
    const glm::dvec3 p = r.origin + t * r.dir;
    const double rho2 = p.x * p.x + p.y * p.y;
    if (rho2 <= rho_hi * rho_hi && rho2 >= rho_lo * rho_lo) near.offer(t);
}

double rho(const glm::dvec3& p) { return std::sqrt(p.x * p.x + p.y * p.y); }

glm::dvec3 around(double phi) { return {-std::sin(phi), std::cos(phi), 0.0}; }

// A uniform point on the annulus rho_lo..rho_hi of the plane z, facing nz.
SurfacePoint annulus_point(Rng& rng, double z, double rho_lo, double rho_hi, double nz) {
    const double r = std::sqrt(rng.uniform(rho_lo * rho_lo, rho_hi * rho_hi)), phi = 2.0 * kPi * rng.uniform();
    SurfacePoint s;
    s.p = {r * std::cos(phi), r * std::sin(phi), z};
    s.n = {0.0, 0.0, nz};
    s.tangent = around(phi);
    s.feature = rho_lo > 0.0 ? std::min(r - rho_lo, rho_hi - r) : rho_hi - r;
    return s;
}

double annulus_area(double lo, double hi) { return kPi * (hi * hi - lo * lo); }

class Ellipsoid final : public Primitive {
public:
    Ellipsoid(glm::dvec3 radii, double z_cut) : r_(radii), z_cut_(std::max(z_cut, -radii.z)) {
        // Curved area by midpoint quadrature over the cut sphere's (theta, phi).
        const int nt = 96, np = 192;
        const double c_lo = -1.0, c_hi = std::min(1.0, -z_cut_ / r_.z);  // cos(theta) range of z >= z_cut
        for (int i = 0; i < nt; ++i) {
            const double c = c_hi + (c_lo - c_hi) * (i + 0.5) / nt;  // cos(theta), theta from +z
            const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
            for (int j = 0; j < np; ++j) {
                const double phi = 2.0 * kPi * (j + 0.5) / np;
                const glm::dvec3 u(s * std::cos(phi), s * std::sin(phi), -c);
                curved_area_ += area_factor(u);
            }
        }
        curved_area_ *= (c_hi - c_lo) / nt * 2.0 * kPi / np;  // d(area) = factor * d(cos) d(phi)
        const double q = z_cut_ / r_.z;
        cut_scale_ = z_cut_ > -r_.z ? std::sqrt(std::max(0.0, 1.0 - q * q)) : 0.0;
        cut_area_ = kPi * r_.x * r_.y * cut_scale_ * cut_scale_;
        max_factor_ = r_.x * r_.y * r_.z / std::min({r_.x, r_.y, r_.z});
    }

    bool intersect(const Ray& r, double t_min, double t_max, double& t) const override {
        const glm::dvec3 o = r.origin / r_, d = r.dir / r_;
        double t0, t1;
        if (solve_quadratic(glm::dot(d, d), 2.0 * glm::dot(o, d), glm::dot(o, o) - 1.0, t0, t1) < 2) return false;
        double lo = t0, hi = t1;
        if (z_cut_ > -r_.z) {
            if (r.dir.z == 0.0) {
                if (r.origin.z < z_cut_) return false;
            } else {
                const double tc = (z_cut_ - r.origin.z) / r.dir.z;
                if (r.dir.z > 0.0) lo = std::max(lo, tc);
                else hi = std::min(hi, tc);
            }
            if (lo > hi) return false;
        }
        const double hit = lo > t_min ? lo : hi;
        if (hit <= t_min || hit >= t_max) return false;
        t = hit;
        return true;
    }

    bool contains(const glm::dvec3& p) const override {
        const glm::dvec3 q = p / r_;
        return glm::dot(q, q) <= 1.0 && p.z >= z_cut_;
    }

    double area() const override { return curved_area_ + cut_area_; }
    Aabb bounds() const override { return Aabb{glm::dvec3(-r_.x, -r_.y, z_cut_), r_}; }

    SurfacePoint sample(Rng& rng) const override {
        SurfacePoint s;
        if (rng.uniform() * area() < cut_area_) {
            s = annulus_point(rng, z_cut_, 0.0, 1.0, -1.0);
            s.feature *= std::min(r_.x, r_.y) * cut_scale_;
            s.p.x *= r_.x * cut_scale_;
            s.p.y *= r_.y * cut_scale_;
            return s;
        }
        // Rejection from the sphere, by the area stretch of the map u -> radii * u.
        for (int tries = 0; tries < 100000; ++tries) {
            const glm::dvec3 u = uniform_on_sphere(rng);
            const glm::dvec3 p = u * r_;
            if (p.z < z_cut_) continue;
            if (rng.uniform() * max_factor_ > area_factor(u)) continue;
            s.p = p;
            s.n = glm::normalize(p / (r_ * r_));
            const glm::dvec3 t(-s.n.y, s.n.x, 0.0);
            s.tangent = glm::length(t) > 1e-6 ? glm::normalize(t) : glm::dvec3(1, 0, 0);
            s.feature = 0.7 * std::min({r_.x, r_.y, r_.z});
            if (cut_area_ > 0.0) s.feature = std::min(s.feature, 2.0 * (p.z - z_cut_));
            return s;
        }
        s.p = glm::dvec3(0.0, 0.0, r_.z);
        return s;
    }

private:
    // Ratio of ellipsoid area to unit-sphere area at the sphere point u.
    double area_factor(const glm::dvec3& u) const { return r_.x * r_.y * r_.z * glm::length(u / r_); }

    glm::dvec3 r_;
    double z_cut_;
    double curved_area_ = 0.0, cut_area_ = 0.0, cut_scale_ = 0.0, max_factor_ = 1.0;
};

class Cylinder final : public Primitive {
public:
    Cylinder(double radius, double height, double inner, double floor)
        : R_(radius), h_(height), ri_(std::clamp(inner, 0.0, radius)), f_(ri_ > 0.0 ? std::clamp(floor, 0.0, height) : 0.0) {
        parts_.push(2.0 * kPi * R_ * h_);                            // outer wall
        parts_.push(ri_ > 0.0 ? 2.0 * kPi * ri_ * (h_ - f_) : 0.0);  // inner wall
        parts_.push(annulus_area(ri_, R_));                          // top rim or cap
        parts_.push(annulus_area(bottom_lo(), R_));                  // bottom
        parts_.push(ri_ > 0.0 && f_ > 0.0 ? annulus_area(0.0, ri_) : 0.0);  // floor inside
    }

    bool intersect(const Ray& r, double t_min, double t_max, double& t) const override {
        Nearest near{t_min, t_max};
        double t0, t1;
        if (cylinder_roots(r, R_, t0, t1))
            for (double tc : {t0, t1}) {
                const double z = r.origin.z + tc * r.dir.z;
                if (z >= 0.0 && z <= h_) near.offer(tc);
            }
        if (ri_ > 0.0 && cylinder_roots(r, ri_, t0, t1))
            for (double tc : {t0, t1}) {
                const double z = r.origin.z + tc * r.dir.z;
                if (z >= f_ && z <= h_) near.offer(tc);
            }
        offer_disc(near, r, h_, ri_, R_);
        offer_disc(near, r, 0.0, bottom_lo(), R_);
        if (ri_ > 0.0 && f_ > 0.0) offer_disc(near, r, f_, 0.0, ri_);
        if (near.best >= t_max) return false;
        t = near.best;
        return true;
    }

    bool contains(const glm::dvec3& p) const override {
        if (p.z < 0.0 || p.z > h_) return false;
        const double q = rho(p);
        return q <= R_ && (q >= ri_ || p.z <= f_);
    }

    double area() const override { return parts_.total(); }
    Aabb bounds() const override { return Aabb{glm::dvec3(-R_, -R_, 0.0), glm::dvec3(R_, R_, h_)}; }

    SurfacePoint sample(Rng& rng) const override {
        switch (parts_.pick(rng)) {
            case 0: return wall(rng, R_, 0.0, 1.0);
            case 1: return wall(rng, ri_, f_, -1.0);
            case 2: return annulus_point(rng, h_, ri_, R_, 1.0);
            case 3: return annulus_point(rng, 0.0, bottom_lo(), R_, -1.0);
            default: return annulus_point(rng, f_, 0.0, ri_, 1.0);
        }
    }

private:
    double bottom_lo() const { return f_ > 0.0 ? 0.0 : ri_; }

    SurfacePoint wall(Rng& rng, double radius, double z0, double outward) const {
        const double phi = 2.0 * kPi * rng.uniform(), z = rng.uniform(z0, h_);
        SurfacePoint s;
        const glm::dvec3 radial(std::cos(phi), std::sin(phi), 0.0);
        s.p = radius * radial + glm::dvec3(0.0, 0.0, z);
        s.n = outward * radial;
        s.tangent = around(phi);
        s.feature = std::min({z - z0, h_ - z, 0.8 * radius});
        return s;
    }

    double R_, h_, ri_, f_;
    AreaTable parts_;
};

class Cone final : public Primitive {
public:
    Cone(double r0, double r1, double height) : r0_(r0), r1_(r1), h_(height), k_((r1 - r0) / height) {
        slant_ = std::sqrt(h_ * h_ + (r1_ - r0_) * (r1_ - r0_));
        parts_.push(kPi * (r0_ + r1_) * slant_);
        parts_.push(annulus_area(0.0, r0_));
        parts_.push(annulus_area(0.0, r1_));
    }

    bool intersect(const Ray& r, double t_min, double t_max, double& t) const override {
        Nearest near{t_min, t_max};
        const glm::dvec3 o = r.origin, d = r.dir;
        const double base = r0_ + k_ * o.z;
        const double a = d.x * d.x + d.y * d.y - k_ * k_ * d.z * d.z;
        const double b = 2.0 * (o.x * d.x + o.y * d.y - k_ * d.z * base);
        const double c = o.x * o.x + o.y * o.y - base * base;
        double t0, t1;
        if (solve_quadratic(a, b, c, t0, t1))
            for (double tc : {t0, t1}) {
                const double z = o.z + tc * d.z;
                if (z >= 0.0 && z <= h_) near.offer(tc);
            }
        offer_disc(near, r, 0.0, 0.0, r0_);
        offer_disc(near, r, h_, 0.0, r1_);
        if (near.best >= t_max) return false;
        t = near.best;
        return true;
    }

    bool contains(const glm::dvec3& p) const override {
        return p.z >= 0.0 && p.z <= h_ && rho(p) <= r0_ + k_ * p.z;
    }

    double area() const override { return parts_.total(); }
    Aabb bounds() const override {
        const double m = std::max(r0_, r1_);
        return Aabb{glm::dvec3(-m, -m, 0.0), glm::dvec3(m, m, h_)};
    }

    SurfacePoint sample(Rng& rng) const override {
        const size_t part = parts_.pick(rng);
        if (part == 1) return annulus_point(rng, 0.0, 0.0, r0_, -1.0);
        if (part == 2) return annulus_point(rng, h_, 0.0, r1_, 1.0);
        // Along the slant with density proportional to the radius there.
        const double u = rng.uniform();
        const double w = std::abs(r1_ - r0_) < 1e-9 * (r0_ + r1_)
                             ? u
                             : (-r0_ + std::sqrt(r0_ * r0_ + u * (r1_ * r1_ - r0_ * r0_))) / (r1_ - r0_);
        const double phi = 2.0 * kPi * rng.uniform(), radius = r0_ + (r1_ - r0_) * w;
        const glm::dvec3 radial(std::cos(phi), std::sin(phi), 0.0);
        SurfacePoint s;
        s.p = radius * radial + glm::dvec3(0.0, 0.0, w * h_);
        s.n = glm::normalize(radial - glm::dvec3(0.0, 0.0, k_));
        s.tangent = around(phi);
        s.feature = std::min({w * slant_, (1.0 - w) * slant_, 0.8 * radius});
        return s;
    }

private:
    double r0_, r1_, h_, k_, slant_;
    AreaTable parts_;
};

class Capsule final : public Primitive {
public:
    Capsule(double radius, double length) : r_(radius), len_(length) {}

    bool intersect(const Ray& r, double t_min, double t_max, double& t) const override {
        Nearest near{t_min, t_max};
        double t0, t1;
        if (cylinder_roots(r, r_, t0, t1)) {
            const double z = r.origin.z + t0 * r.dir.z;
            if (z >= 0.0 && z <= len_) near.offer(t0);
        }
        for (double zc : {0.0, len_})
            if (sphere_roots(r, glm::dvec3(0.0, 0.0, zc), r_, t0, t1)) near.offer(t0);
        if (near.best >= t_max) return false;
        t = near.best;
        return true;
    }

    bool contains(const glm::dvec3& p) const override {
        const glm::dvec3 axis(0.0, 0.0, std::clamp(p.z, 0.0, len_));
        return glm::length(p - axis) <= r_;
    }

    double area() const override { return 2.0 * kPi * r_ * len_ + 4.0 * kPi * r_ * r_; }
    Aabb bounds() const override { return Aabb{glm::dvec3(-r_, -r_, -r_), glm::dvec3(r_, r_, len_ + r_)}; }

    SurfacePoint sample(Rng& rng) const override {
        SurfacePoint s;
        s.feature = 0.8 * r_;
        if (rng.uniform() * area() < 2.0 * kPi * r_ * len_) {
            const double phi = 2.0 * kPi * rng.uniform();
            s.n = glm::dvec3(std::cos(phi), std::sin(phi), 0.0);
            s.p = r_ * s.n + glm::dvec3(0.0, 0.0, rng.uniform(0.0, len_));
            s.tangent = glm::dvec3(0.0, 0.0, 1.0);
            return s;
        }
        s.n = uniform_on_sphere(rng);
        s.p = r_ * s.n + glm::dvec3(0.0, 0.0, s.n.z > 0.0 ? len_ : 0.0);
        s.tangent = perpendicular(s.n);
        return s;
    }

private:
    double r_, len_;
};

}  // namespace

PrimitivePtr make_ellipsoid(const glm::dvec3& radii, double z_cut) { return std::make_shared<Ellipsoid>(radii, z_cut); }
PrimitivePtr make_cylinder(double radius, double height, double inner_radius, double floor) {
    return std::make_shared<Cylinder>(radius, height, inner_radius, floor);
}
PrimitivePtr make_cone(double r0, double r1, double height) { return std::make_shared<Cone>(r0, r1, height); }
PrimitivePtr make_capsule(double radius, double length) { return std::make_shared<Capsule>(radius, length); }

}  // namespace pg::data::synth

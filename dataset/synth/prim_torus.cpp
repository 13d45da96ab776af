// Torus (or an arc of one, for handles): the ray-torus quartic solved on the stretch of the
// ray inside the bounding sphere, shifted there so the coefficients stay well conditioned.
#include <cmath>

#include "dataset/synth/poly_roots.h"
#include "dataset/synth/primitives.h"
#include "dataset/synth/sampling.h"

namespace pg::data::synth {
namespace {

class Torus final : public Primitive {
public:
    Torus(double major, double minor, double phi0, double phi1)
        : R_(major), r_(minor), phi0_(phi0), span_(std::min(phi1 - phi0, 2.0 * kPi)) {
        full_ = span_ >= 2.0 * kPi - 1e-12;
        parts_.push(2.0 * kPi * r_ * R_ * span_);
        parts_.push(full_ ? 0.0 : 2.0 * kPi * r_ * r_);
    }

    bool intersect(const Ray& r, double t_min, double t_max, double& t) const override {
        const double len = glm::length(r.dir);
        if (len == 0.0) return false;
        const glm::dvec3 d = r.dir / len;
        double ta, tb;
        const double bound = R_ + r_;
        if (solve_quadratic(1.0, 2.0 * glm::dot(r.origin, d), glm::dot(r.origin, r.origin) - bound * bound, ta, tb) < 2)
            return false;
        const double lo = std::max(ta, t_min * len), hi = std::min(tb, t_max * len);
        if (lo > hi) return false;
        const double base = ta;
        const glm::dvec3 o = r.origin + base * d;
        const double B = 2.0 * glm::dot(o, d), C = glm::dot(o, o) + R_ * R_ - r_ * r_;
        const double a2 = d.x * d.x + d.y * d.y, a1 = 2.0 * (o.x * d.x + o.y * d.y), a0 = o.x * o.x + o.y * o.y;
        const double k = 4.0 * R_ * R_;
        const double c[5] = {C * C - k * a0, 2.0 * B * C - k * a1, B * B + 2.0 * C - k * a2, 2.0 * B, 1.0};
        double roots[8];
        const int n = poly_roots(c, 4, lo - base, hi - base, roots);
        double best = kInf;
        for (int i = 0; i < n; ++i) {
            const double s = roots[i] + base;
            if (s <= t_min * len) continue;
            const glm::dvec3 p = r.origin + s * d;
            if (in_range(std::atan2(p.y, p.x))) {
                best = s;
                break;
            }
        }
        if (!full_)
            for (double phi : {phi0_, phi0_ + span_}) {
                const glm::dvec3 centre(R_ * std::cos(phi), R_ * std::sin(phi), 0.0), n_cap(-std::sin(phi), std::cos(phi), 0.0);
                const double dn = glm::dot(n_cap, d);
                if (dn == 0.0) continue;
                const double s = glm::dot(n_cap, centre - r.origin) / dn;
                if (s > t_min * len && s < best && glm::length(r.origin + s * d - centre) <= r_) best = s;
            }
        if (!(best < t_max * len)) return false;
        t = best / len;
        return true;
    }

    bool contains(const glm::dvec3& p) const override {
        const double q = std::sqrt(p.x * p.x + p.y * p.y) - R_;
        return q * q + p.z * p.z <= r_ * r_ && in_range(std::atan2(p.y, p.x));
    }

    double area() const override { return parts_.total(); }
    Aabb bounds() const override {
        const double m = R_ + r_;
        return Aabb{glm::dvec3(-m, -m, -r_), glm::dvec3(m, m, r_)};
    }

    SurfacePoint sample(Rng& rng) const override {
        SurfacePoint s;
        s.feature = 0.8 * r_;
        if (parts_.pick(rng) == 1) {  // an end cap
            const double phi = rng.chance(0.5) ? phi0_ : phi0_ + span_;
            const double side = phi == phi0_ ? -1.0 : 1.0;
            const glm::dvec3 radial(std::cos(phi), std::sin(phi), 0.0), n_cap(-std::sin(phi), std::cos(phi), 0.0);
            const double q = r_ * std::sqrt(rng.uniform()), a = 2.0 * kPi * rng.uniform();
            s.p = R_ * radial + q * (std::cos(a) * radial + std::sin(a) * glm::dvec3(0, 0, 1));
            s.n = side * n_cap;
            s.tangent = radial;
            s.feature = std::max(1e-9, r_ - q);
            return s;
        }
        const double phi = phi0_ + span_ * rng.uniform();
        double psi = 0.0;
        for (int tries = 0; tries < 1000; ++tries) {
            psi = 2.0 * kPi * rng.uniform();
            if (rng.uniform() * (R_ + r_) <= R_ + r_ * std::cos(psi)) break;
        }
        const glm::dvec3 radial(std::cos(phi), std::sin(phi), 0.0);
        s.n = std::cos(psi) * radial + glm::dvec3(0.0, 0.0, std::sin(psi));
        s.p = R_ * radial + r_ * s.n;
        s.tangent = glm::dvec3(-std::sin(phi), std::cos(phi), 0.0);
        return s;
    }

private:
    bool in_range(double phi) const {
        if (full_) return true;
        double a = std::fmod(phi - phi0_, 2.0 * kPi);
        if (a < 0.0) a += 2.0 * kPi;
        return a <= span_;
    }

    double R_, r_, phi0_, span_;
    bool full_ = true;
    AreaTable parts_;
};

}  // namespace

PrimitivePtr make_torus(double major, double minor, double phi0, double phi1) {
    return std::make_shared<Torus>(major, minor, phi0, phi1);
}

}  // namespace pg::data::synth

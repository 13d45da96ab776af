// A box with rounded edges: the union of three slabs, twelve edge cylinders and eight corner
// spheres. From outside, the first hit of the union is the nearest entry into any part.
#include <cmath>

#include "dataset/synth/primitives.h"
#include "dataset/synth/sampling.h"

namespace pg::data::synth {
namespace {

class RoundedBox final : public Primitive {
public:
    RoundedBox(glm::dvec3 half, double radius) : h_(half), r_(std::clamp(radius, 0.0, std::min({half.x, half.y, half.z}))) {
        c_ = h_ - glm::dvec3(r_);  // the inner box whose offset by r is the solid
        for (int a = 0; a < 3; ++a) parts_.push(2.0 * 4.0 * c_[(a + 1) % 3] * c_[(a + 2) % 3]);  // face pairs
        for (int a = 0; a < 3; ++a) parts_.push(4.0 * 0.5 * kPi * r_ * 2.0 * c_[a]);            // edges along a
        parts_.push(4.0 * kPi * r_ * r_);                                                       // corners
    }

    bool intersect(const Ray& r, double t_min, double t_max, double& t) const override {
        double best = t_max;
        auto offer = [&](double tc) {
            if (tc > t_min && tc < best) best = tc;
        };
        // Slabs: the box grown by r along one axis.
        for (int a = 0; a < 3; ++a) {
            glm::dvec3 half = c_;
            half[a] = h_[a];
            double lo = -kInf, hi = kInf;
            bool miss = false;
            for (int k = 0; k < 3 && !miss; ++k) {
                if (r.dir[k] == 0.0) {
                    miss = std::abs(r.origin[k]) > half[k];
                    continue;
                }
                double ta = (-half[k] - r.origin[k]) / r.dir[k], tb = (half[k] - r.origin[k]) / r.dir[k];
                if (ta > tb) std::swap(ta, tb);
                lo = std::max(lo, ta);
                hi = std::min(hi, tb);
                miss = lo > hi;
            }
            if (!miss) offer(lo > t_min ? lo : hi);
        }
        if (r_ <= 0.0) return finish(best, t_max, t);
        // Edge cylinders along axis a, through (+-c_b, +-c_c).
        for (int a = 0; a < 3; ++a) {
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            const double qa = r.dir[b] * r.dir[b] + r.dir[c] * r.dir[c];
            if (qa == 0.0) continue;
            for (double sb : {-1.0, 1.0})
                for (double sc : {-1.0, 1.0}) {
                    const double ob = r.origin[b] - sb * c_[b], oc = r.origin[c] - sc * c_[c];
                    double t0, t1;
                    if (!solve_quadratic(qa, 2.0 * (ob * r.dir[b] + oc * r.dir[c]), ob * ob + oc * oc - r_ * r_, t0, t1))
                        continue;
                    const double x = r.origin[a] + t0 * r.dir[a];
                    if (std::abs(x) <= c_[a]) offer(t0);
                }
        }
        for (int i = 0; i < 8; ++i) {
            const glm::dvec3 centre(i & 1 ? c_.x : -c_.x, i & 2 ? c_.y : -c_.y, i & 4 ? c_.z : -c_.z);
            const glm::dvec3 o = r.origin - centre;
            double t0, t1;
            if (solve_quadratic(glm::dot(r.dir, r.dir), 2.0 * glm::dot(o, r.dir), glm::dot(o, o) - r_ * r_, t0, t1))
                offer(t0);
        }
        return finish(best, t_max, t);
    }

    bool contains(const glm::dvec3& p) const override {
        const glm::dvec3 q = glm::max(glm::abs(p) - c_, glm::dvec3(0.0));
        return glm::dot(q, q) <= r_ * r_;
    }

    double area() const override { return parts_.total(); }
    Aabb bounds() const override { return Aabb{-h_, h_}; }

    SurfacePoint sample(Rng& rng) const override {
        const size_t part = parts_.pick(rng);
        SurfacePoint s;
        if (part < 3) {  // a flat face with normal along axis `part`
            const int a = int(part), b = (a + 1) % 3, c = (a + 2) % 3;
            const double sign = rng.sign();
            s.p[a] = sign * h_[a];
            s.p[b] = rng.uniform(-c_[b], c_[b]);
            s.p[c] = rng.uniform(-c_[c], c_[c]);
            s.n = glm::dvec3(0.0);
            s.n[a] = sign;
            s.tangent = glm::dvec3(0.0);
            s.tangent[a == 2 ? 0 : (a == 0 ? 1 : 0)] = 1.0;  // horizontal on the sides, x on top
            s.feature = r_ + std::min(c_[b] - std::abs(s.p[b]), c_[c] - std::abs(s.p[c]));
            return s;
        }
        if (part < 6) {  // a quarter cylinder along axis a
            const int a = int(part) - 3, b = (a + 1) % 3, c = (a + 2) % 3;
            const double sb = rng.sign(), sc = rng.sign(), ang = 0.5 * kPi * rng.uniform();
            s.n = glm::dvec3(0.0);
            s.n[b] = sb * std::cos(ang);
            s.n[c] = sc * std::sin(ang);
            s.p = r_ * s.n;
            s.p[a] = rng.uniform(-c_[a], c_[a]);
            s.p[b] += sb * c_[b];
            s.p[c] += sc * c_[c];
            s.tangent = glm::dvec3(0.0);
            s.tangent[a] = 1.0;
            s.feature = 0.8 * r_;
            return s;
        }
        s.n = uniform_on_sphere(rng);  // corner octants: the sphere's signs pick the corner
        s.p = r_ * s.n + glm::dvec3(s.n.x < 0 ? -c_.x : c_.x, s.n.y < 0 ? -c_.y : c_.y, s.n.z < 0 ? -c_.z : c_.z);
        s.tangent = perpendicular(s.n);
        s.feature = 0.8 * r_;
        return s;
    }

private:
    static bool finish(double best, double t_max, double& t) {
        if (best >= t_max) return false;
        t = best;
        return true;
    }

    glm::dvec3 h_, c_;
    double r_;
    AreaTable parts_;
};

}  // namespace

PrimitivePtr make_rounded_box(const glm::dvec3& half, double radius) { return std::make_shared<RoundedBox>(half, radius); }

}  // namespace pg::data::synth

// SplatSeg-Synth primitives: exact first hits against an independent march of the inside
// test, surface samples on the surface with outward normals, areas against closed forms,
// and sampling proportional to area.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "dataset/synth/poly_roots.h"
#include "dataset/synth/primitives.h"
#include "dataset/synth/sampling.h"

using namespace pg::data::synth;

namespace {

struct Named {
    std::string name;
    PrimitivePtr prim;
};

std::vector<Named> catalogue() {
    std::vector<double> hills;
    for (int j = 0; j < 9; ++j)
        for (int i = 0; i < 11; ++i) hills.push_back(0.3 * std::sin(0.9 * i) * std::cos(0.7 * j) + 0.05 * ((i * 7 + j * 3) % 5));
    return {
        {"box", make_box({0.3, 0.5, 0.2})},
        {"prism", make_prism({{0, 0}, {1, 0}, {1.2, 0.6}, {0.4, 1.0}}, -0.2, 0.3)},
        {"tapered box", make_tapered_box({0.8, 0.5}, {0.4, 0.3}, 0.6, {-0.2, 0.05})},
        {"gable roof", make_gable_roof(2.0, 1.2, 0.7)},
        {"hip roof", make_hip_roof(2.0, 1.2, 0.7, 0.8)},
        {"rounded box", make_rounded_box({0.5, 0.3, 0.2}, 0.08)},
        {"sphere", make_ellipsoid(glm::dvec3(0.4))},
        {"ellipsoid", make_ellipsoid({0.6, 0.3, 0.2})},
        {"dome", make_ellipsoid({0.5, 0.4, 0.3}, 0.05)},
        {"cylinder", make_cylinder(0.3, 0.8)},
        {"cup", make_cylinder(0.3, 0.8, 0.25, 0.06)},
        {"tube", make_cylinder(0.3, 0.2, 0.2)},
        {"frustum", make_cone(0.4, 0.15, 0.5)},
        {"cone", make_cone(0.3, 0.0, 0.6)},
        {"capsule", make_capsule(0.05, 0.9)},
        {"torus", make_torus(0.4, 0.1)},
        {"handle", make_torus(0.3, 0.06, -1.5, 1.5)},
        {"heightfield", make_heightfield(11, 9, 2.0, 1.6, hills, -0.5)},
    };
}

// The first t > 0 at which the ray is inside, by marching the box span and bisecting.
bool march(const Primitive& prim, const Ray& ray, double step, double& t_out) {
    const Aabb b = prim.bounds();
    const Aabb grown{b.lo - glm::dvec3(1e-6), b.hi + glm::dvec3(1e-6)};
    double t0, t1;
    if (!ray_box(ray, 1.0 / ray.dir, grown, t0, t1)) return false;
    for (double t = std::max(t0, 0.0); t <= t1 + step; t += step) {
        if (!prim.contains(ray.origin + t * ray.dir)) continue;
        double lo = t - step, hi = t;
        for (int k = 0; k < 60; ++k) {
            const double mid = 0.5 * (lo + hi);
            (prim.contains(ray.origin + mid * ray.dir) ? hi : lo) = mid;
        }
        t_out = hi;
        return true;
    }
    return false;
}

}  // namespace

TEST_CASE("synth primitives: first hits agree with a march of the inside test", "[synth]") {
    for (const Named& n : catalogue()) {
        const Aabb b = n.prim->bounds();
        const double diag = glm::length(b.size());
        const double step = diag / 1500.0;
        Rng rng(17);
        int rays = 0, hits = 0, mismatches = 0;
        for (int k = 0; k < 200; ++k) {
            // From outside the bounds towards a point in (or near) them.
            glm::dvec3 dir;
            do dir = glm::dvec3(rng.normal(), rng.normal(), rng.normal());
            while (glm::length(dir) < 1e-3);
            const glm::dvec3 origin = b.centre() + 1.5 * diag * glm::normalize(dir);
            const glm::dvec3 target = b.lo + (b.hi - b.lo) * glm::dvec3(rng.uniform(-0.1, 1.1), rng.uniform(-0.1, 1.1), rng.uniform(-0.1, 1.1));
            const Ray ray{origin, glm::normalize(target - origin)};
            double t = 0.0, t_ref = 0.0;
            const bool hit = n.prim->intersect(ray, 0.0, kInf, t);
            const bool ref = march(*n.prim, ray, step, t_ref);
            ++rays;
            hits += ref;
            // A march can step over a grazing sliver; then the exact hit comes earlier.
            if (hit != ref || (hit && std::abs(t - t_ref) > 2.0 * step)) ++mismatches;
        }
        INFO(n.name << ": " << mismatches << " of " << rays << " rays disagree, " << hits << " hit");
        CHECK(hits > 20);
        CHECK(mismatches <= rays / 50);
    }
}

TEST_CASE("synth primitives: hits land on the surface and respect t_min and t_max", "[synth]") {
    for (const Named& n : catalogue()) {
        const Aabb b = n.prim->bounds();
        const double diag = glm::length(b.size()), eps = 1e-5 * diag;
        Rng rng(5);
        int bad = 0, hits = 0;
        for (int k = 0; k < 300; ++k) {
            const glm::dvec3 origin = b.centre() + 2.0 * diag * uniform_on_sphere(rng);
            const glm::dvec3 target = b.lo + (b.hi - b.lo) * glm::dvec3(rng.uniform(), rng.uniform(), rng.uniform());
            const Ray ray{origin, target - origin};  // not unit: t is in units of |dir|
            double t;
            if (!n.prim->intersect(ray, 0.0, kInf, t)) continue;
            ++hits;
            const glm::dvec3 p = ray.origin + t * ray.dir, d = glm::normalize(ray.dir);
            if (n.prim->contains(p - eps * d) || !n.prim->contains(p + eps * d)) ++bad;
            double t2;
            if (n.prim->intersect(ray, 0.0, t * 0.999, t2)) ++bad;  // nothing nearer than the first hit
        }
        INFO(n.name);
        CHECK(hits > 50);
        CHECK(bad <= hits / 100);
    }
}

TEST_CASE("synth primitives: samples lie on the surface with outward normals", "[synth]") {
    for (const Named& n : catalogue()) {
        const double diag = glm::length(n.prim->bounds().size()), eps = 1e-4 * diag;
        Rng rng(9);
        int bad = 0;
        const int count = 3000;
        for (int k = 0; k < count; ++k) {
            const SurfacePoint s = n.prim->sample(rng);
            const bool on_surface = n.prim->contains(s.p - eps * s.n) && !n.prim->contains(s.p + eps * s.n);
            const bool frame_ok = std::abs(glm::length(s.n) - 1.0) < 1e-6 && std::abs(glm::dot(s.n, s.tangent)) < 1e-6 &&
                                  std::abs(glm::length(s.tangent) - 1.0) < 1e-6 && s.feature > 0.0;
            if (!on_surface || !frame_ok) ++bad;
        }
        INFO(n.name << ": " << bad << " bad samples");
        CHECK(bad <= count / 100);
    }
}

TEST_CASE("synth primitives: areas match closed forms", "[synth]") {
    const double pi = kPi;
    CHECK(make_box({0.3, 0.5, 0.2})->area() == Approx(8 * (0.3 * 0.5 + 0.5 * 0.2 + 0.3 * 0.2)));
    CHECK(make_ellipsoid(glm::dvec3(0.4))->area() == Approx(4 * pi * 0.16).epsilon(1e-4));
    CHECK(make_ellipsoid(glm::dvec3(0.4), 0.0)->area() == Approx(2 * pi * 0.16 + pi * 0.16).epsilon(1e-4));
    // Oblate spheroid a = 0.6, c = 0.3: 2 pi a^2 (1 + (1 - e^2)/e atanh(e)).
    const double e = std::sqrt(1 - 0.25);
    CHECK(make_ellipsoid({0.6, 0.6, 0.3})->area() == Approx(2 * pi * 0.36 * (1 + (1 - e * e) / e * std::atanh(e))).epsilon(1e-4));
    CHECK(make_cylinder(0.3, 0.8)->area() == Approx(2 * pi * 0.3 * 0.8 + 2 * pi * 0.09));
    CHECK(make_cylinder(0.3, 0.8, 0.25, 0.06)->area() ==
          Approx(2 * pi * 0.3 * 0.8 + 2 * pi * 0.25 * 0.74 + pi * (0.09 - 0.0625) + pi * 0.09 + pi * 0.0625));
    CHECK(make_cone(0.4, 0.15, 0.5)->area() == Approx(pi * 0.55 * std::sqrt(0.25 + 0.0625) + pi * 0.16 + pi * 0.0225));
    CHECK(make_capsule(0.05, 0.9)->area() == Approx(2 * pi * 0.05 * 0.9 + 4 * pi * 0.0025));
    CHECK(make_torus(0.4, 0.1)->area() == Approx(4 * pi * pi * 0.4 * 0.1));
    const double r = 0.08;
    const glm::dvec3 c(0.5 - r, 0.3 - r, 0.2 - r);
    CHECK(make_rounded_box({0.5, 0.3, 0.2}, r)->area() ==
          Approx(8 * (c.x * c.y + c.y * c.z + c.z * c.x) + 2 * pi * r * (c.x + c.y + c.z) * 2 + 4 * pi * r * r));
    CHECK(make_heightfield(2, 2, 2.0, 1.0, {0, 0, 0, 0}, -1.0)->area() == Approx(2.0));
}

TEST_CASE("synth primitives: sampling is proportional to area", "[synth]") {
    Rng rng(3);
    const int count = 40000;
    // A 1 x 2 x 3 box: faces normal to x hold 2*6/22 of the area.
    const PrimitivePtr box = make_box({0.5, 1.0, 1.5});
    int x_faces = 0;
    for (int k = 0; k < count; ++k) x_faces += std::abs(box->sample(rng).n.x) > 0.5;
    CHECK(double(x_faces) / count == Approx(12.0 / 22.0).margin(0.01));
    // A cylinder: the wall holds 2 pi r h / (2 pi r h + 2 pi r^2).
    const PrimitivePtr cyl = make_cylinder(0.3, 0.8);
    int wall = 0;
    for (int k = 0; k < count; ++k) wall += std::abs(cyl->sample(rng).n.z) < 0.5;
    CHECK(double(wall) / count == Approx(0.8 / 1.1).margin(0.01));
    // An ellipsoid: samples in the cap z > 0.5 c against its share of the quadrature area.
    const PrimitivePtr ell = make_ellipsoid({0.6, 0.3, 0.2}), cap = make_ellipsoid({0.6, 0.3, 0.2}, 0.1);
    const double cap_curved = cap->area() - kPi * 0.6 * 0.3 * 0.75;  // minus the cut disc
    int in_cap = 0;
    for (int k = 0; k < count; ++k) in_cap += ell->sample(rng).p.z > 0.1;
    CHECK(double(in_cap) / count == Approx(cap_curved / ell->area()).margin(0.01));
}

TEST_CASE("synth primitives: polynomial roots in an interval", "[synth]") {
    // (t - 1)(t - 2)(t + 0.5)(t - 3.5) = t^4 - 6 t^3 + 9.25 t^2 - 0.75 t - 3.5
    const double c[5] = {-3.5, -0.75, 9.25, -6.0, 1.0};
    double roots[8];
    REQUIRE(poly_roots(c, 4, 0.0, 10.0, roots) == 3);
    CHECK(roots[0] == Approx(1.0));
    CHECK(roots[1] == Approx(2.0));
    CHECK(roots[2] == Approx(3.5));
    REQUIRE(poly_roots(c, 4, -1.0, 1.5, roots) == 2);
    CHECK(roots[0] == Approx(-0.5));
    const double none[3] = {1.0, 0.0, 1.0};  // t^2 + 1
    CHECK(poly_roots(none, 2, -5.0, 5.0, roots) == 0);
}

// Vehicles suite: 3-4 cars parked close together along a kerb (one sometimes across the
// street), among lamp posts, meters, signs, bins and street trees, with shop fronts on both
// sides and a sky.
#include <cmath>

#include "dataset/synth/buildings.h"
#include "dataset/synth/suites.h"
#include "dataset/synth/vegetation.h"
#include "dataset/synth/vehicle.h"

namespace pg::data::synth {
namespace {

constexpr double kKerbY = 4.2, kFarKerbY = -9.0, kStreet = 70.0;
constexpr double kGroundSigma = 0.16, kFurnitureSigma = 0.03, kCarSigma = 0.032, kFacadeSigma = 0.25, kTreeSigma = 0.085;

Material mat(Albedo a, float gloss = 0.03f, float aligned = 0.0f) {
    Material m;
    m.albedo = std::move(a);
    m.gloss = gloss;
    m.aligned = aligned;
    return m;
}

void add_street(Layout& L, Rng& rng) {
    const uint64_t seed = rng.next();
    const Albedo tarmac = asphalt(glm::vec3(0.24f, 0.24f, 0.25f), seed);
    const double centre_line = 0.5 * (kKerbY + kFarKerbY);
    auto road = [=](const glm::dvec3& p, const glm::dvec3& n) {
        const glm::vec3 paint(0.85f, 0.85f, 0.8f);
        if (n.z > 0.9) {
            if (std::abs(p.y - centre_line) < 0.08 && std::fmod(p.x + 1000.0, 9.0) < 3.0) return paint;  // dashes
            if (std::abs(p.y - (kKerbY - 2.3)) < 0.06) return paint;                                     // parking lane
            if (std::abs(p.y - (kFarKerbY + 0.3)) < 0.06) return paint;
        }
        return tarmac(p, n);
    };
    L.add(make_box({kStreet, 0.5 * (kKerbY - kFarKerbY), 0.2}), Frame::at({0, 0.5 * (kKerbY + kFarKerbY), -0.2}), mat(road),
          kGroundSigma);
    // Kerbs and pavements on both sides.
    const Albedo slabs = [](const glm::dvec3& p, const glm::dvec3&) {
        const bool joint = std::fmod(p.x + 1000.0, 0.6) < 0.02 || std::fmod(p.y + 1000.0, 0.6) < 0.02;
        return joint ? glm::vec3(0.4f) : glm::vec3(0.6f, 0.58f, 0.55f);
    };
    for (double side : {1.0, -1.0}) {
        const double kerb = side > 0 ? kKerbY : kFarKerbY, far = side > 0 ? 18.0 : -16.0;
        L.add(make_box({kStreet, 0.1, 0.1}), Frame::at({0, kerb + side * 0.1, 0.05}), mat(plain(glm::vec3(0.7f), 0.05f, 0.5)),
              kGroundSigma);
        const double y0 = kerb + side * 0.2;
        L.add(make_box({kStreet, 0.5 * std::abs(far - y0), 0.15}), Frame::at({0, 0.5 * (y0 + far), 0.0}), mat(slabs),
              kGroundSigma);
        // Shop fronts and flats, a row of blocks of varied height.
        for (double x = -kStreet; x < kStreet;) {
            const double w = rng.uniform(8.0, 16.0), h = rng.uniform(7.0, 22.0), d = 12.0;
            FacadeStyle st;
            st.wall = hsv(float(rng.uniform(0.02, 0.12)), float(rng.uniform(0.1, 0.45)), float(rng.uniform(0.45, 0.85)));
            st.bricks = rng.chance(0.4);
            st.storey = 3.2;
            st.bay = w / std::round(w / 3.0);
            st.seed = rng.next();
            st.door = false;
            CampusBuildingSpec b;
            b.length = w;
            b.depth = d;
            b.height = h;
            b.facade = st;
            b.sink = 0.5;
            const Frame f = Frame::at({x + 0.5 * w, far + side * 0.5 * d, 0.15}) * Frame::rotation({0, 0, 1}, side > 0 ? 0.0 : kPi);
            for (const Part& p : make_campus_building(rng, b))
                L.add(p.prim, f * p.frame, p.material, kFacadeSigma);
            x += w;
        }
    }
}

// Street furniture by the cars between x_lo and x_hi; street trees only beyond |x| = clear,
// out of the way of the cameras.
void add_furniture(Layout& L, Rng& rng, double x_lo, double x_hi, double clear) {
    const glm::vec3 metal(0.25f, 0.27f, 0.28f);
    const double y = kKerbY + 0.6;
    Material steel = mat(plain(metal, 0.05f, 0.5), 0.15f, 1.0f);
    // Lamp posts: pole, arm and head.
    for (double x = rng.uniform(-30.0, -22.0); x < 30.0; x += rng.uniform(14.0, 20.0)) {
        L.add(make_capsule(0.08, 6.5), Frame::at({x, y, 0.15}), steel, kFurnitureSigma);
        L.add(make_capsule(0.05, 1.6), Frame::at({x, y, 6.5}) * Frame::rotation({1, 0, 0}, 1.4), steel, kFurnitureSigma);
        L.add(make_rounded_box({0.25, 0.15, 0.08}, 0.04), Frame::at({x, y - 1.55, 6.65}), mat(plain(glm::vec3(0.85f))),
              kFurnitureSigma);
    }
    // Parking meters, bollards, a sign and a bin near the cars: thin background right beside them.
    const int n = rng.between(3, 6);
    for (int k = 0; k < n; ++k) {
        const double x = rng.uniform(x_lo, x_hi), yy = y + rng.uniform(-0.2, 0.4);
        switch (rng.below(4)) {
            case 0:
                L.add(make_capsule(0.04, 1.1), Frame::at({x, yy, 0.15}), steel, kFurnitureSigma);
                L.add(make_rounded_box({0.1, 0.08, 0.2}, 0.03), Frame::at({x, yy, 1.35}), mat(plain(glm::vec3(0.2f, 0.3f, 0.5f))),
                      kFurnitureSigma);
                break;
            case 1: L.add(make_cylinder(0.1, 0.9), Frame::at({x, yy, 0.15}), steel, kFurnitureSigma); break;
            case 2: {
                L.add(make_capsule(0.035, 2.6), Frame::at({x, yy, 0.15}), steel, kFurnitureSigma);
                const glm::vec3 face = rng.chance(0.5) ? glm::vec3(0.1f, 0.3f, 0.7f) : glm::vec3(0.8f, 0.1f, 0.1f);
                L.add(make_cylinder(0.3, 0.02), Frame::at({x, yy - 0.05, 2.5}) * Frame::rotation({1, 0, 0}, 0.5 * kPi),
                      mat(plain(face, 0.02f)), kFurnitureSigma);
                break;
            }
            default:
                L.add(make_cylinder(0.28, 0.95, 0.25, 0.03), Frame::at({x, yy + 0.5, 0.15}), mat(plain(glm::vec3(0.15f, 0.3f, 0.2f))),
                      kFurnitureSigma);
        }
    }
    // Street trees in the pavement, crowns reaching over the parked cars.
    for (double x = rng.uniform(-40.0, -32.0); x < 40.0; x += rng.uniform(8.0, 13.0)) {
        if (std::abs(x) < clear) continue;
        const Frame f = Frame::at({x, kKerbY + rng.uniform(1.1, 1.8), 0.15}) * Frame::rotation({0, 0, 1}, rng.uniform(0, 6.3));
        for (const Part& p : make_tree(rng, rng.uniform(6.0, 9.0), false))
            L.add(p.prim, f * p.frame, p.material, kTreeSigma * p.sigma_scale);
    }
}

}  // namespace

std::vector<ClassInfo> vehicles_classes() { return {{0, "background"}, {1, "car"}}; }

Layout build_vehicles(uint64_t seed) {
    Rng rng(seed);
    Layout L;
    L.default_sh_degree = 3;
    L.classes = vehicles_classes();
    add_street(L, rng);

    // Parked cars, bumper to bumper with small gaps; neighbours often the same colour.
    const int count = rng.between(3, 4);
    const bool across = count == 4 && rng.chance(0.35);
    double x = 0.0;
    std::vector<double> centres;
    glm::vec3 previous = car_paint(rng);
    glm::dvec2 sum(0.0);
    for (int k = 0; k < count; ++k) {
        const glm::vec3 paint = rng.chance(0.4) ? previous : car_paint(rng);
        previous = paint;
        const CarShape car = make_car(rng, paint);
        const int id = L.add_instance(1, "car_" + std::to_string(k + 1));
        glm::dvec3 pos;
        double yaw = (rng.chance(0.8) ? 0.0 : kPi) + 0.03 * rng.normal();
        if (across && k == count - 1) {
            pos = glm::dvec3(rng.uniform(-3.0, 3.0), kFarKerbY + 1.2 + 0.5 * car.width, 0.0);
            yaw = kPi + 0.03 * rng.normal();
        } else {
            pos = glm::dvec3(x + 0.5 * car.length, kKerbY - 0.25 - 0.5 * car.width + 0.1 * rng.normal(), 0.0);
            x += car.length + rng.uniform(0.4, 1.4);
        }
        L.add_parts(car.parts, Frame::at(pos) * Frame::rotation({0, 0, 1}, yaw), kCarSigma, id, 1);
        sum += glm::dvec2(pos);
    }
    // Centre the row of cars on x = 0 by shifting every car shape.
    const double shift = -0.5 * x;
    for (Shape& s : L.shapes)
        if (s.instance > 0 && s.frame.origin.y > 0.0) s.frame.origin.x += shift;
    sum.x += shift * (across ? count - 1 : count);
    const glm::dvec2 centre = sum / double(count);
    L.orbit.target = glm::dvec3(centre, 0.8);
    L.orbit.radius = rng.uniform(9.0, 10.5);
    // Crowns reach 5 m from their trunks at 3-9 m up: none where the cameras circle.
    add_furniture(L, rng, -0.5 * x - 2.0, 0.5 * x + 2.0, L.orbit.radius + 5.0);

    L.orbit.elevations = {8, 20, 35};
    L.orbit.radius_jitter = 0.05;
    L.orbit.target_jitter = 0.3;
    L.orbit.fov_x = 65;
    L.orbit.default_count = 96;
    L.sky.enabled = true;
    L.sky.radius = 400.0;
    L.light.sun = glm::normalize(glm::dvec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(0.9, 1.6)));
    L.light.ambient = 0.5f;
    L.light.direct = 0.55f;
    L.light.shadow = 0.35f;
    L.detail_radius = 14.0;
    L.floater_region = Aabb{glm::dvec3(centre.x - 10, centre.y - 8, 0.3), glm::dvec3(centre.x + 10, centre.y + 8, 5.0)};
    L.floater_sigma = 0.05;
    return L;
}

}  // namespace pg::data::synth

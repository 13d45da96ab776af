#include "dataset/synth/vehicle.h"

#include <cmath>

#include "dataset/synth/texture.h"

namespace pg::data::synth {

glm::vec3 car_paint(Rng& rng) {
    const double r = rng.uniform();
    if (r < 0.25) return glm::vec3(float(rng.uniform(0.55, 0.7)));                   // silver
    if (r < 0.45) return glm::vec3(float(rng.uniform(0.85, 0.93)));                  // white
    if (r < 0.62) return glm::vec3(float(rng.uniform(0.05, 0.12)));                  // black
    if (r < 0.75) return glm::vec3(float(rng.uniform(0.3, 0.4)));                    // grey
    return hsv(float(rng.uniform()), float(rng.uniform(0.5, 0.85)), float(rng.uniform(0.35, 0.75)));
}

CarShape make_car(Rng& rng, glm::vec3 paint) {
    CarShape car;
    const int type = rng.below(3);  // 0 hatchback, 1 sedan, 2 SUV
    const double L = type == 0 ? rng.uniform(3.8, 4.2) : (type == 1 ? rng.uniform(4.4, 4.9) : rng.uniform(4.4, 4.8));
    const double W = rng.uniform(1.72, 1.9), rw = type == 2 ? rng.uniform(0.36, 0.4) : rng.uniform(0.3, 0.34);
    const double z0 = type == 2 ? 0.3 : 0.22, hb = type == 2 ? rng.uniform(0.75, 0.85) : rng.uniform(0.55, 0.65);
    const double hc = type == 2 ? rng.uniform(0.6, 0.7) : rng.uniform(0.45, 0.52);
    car.length = L;
    car.width = W;
    car.height = z0 + hb + hc;

    const glm::vec3 glass(0.08f, 0.1f, 0.12f), chrome(0.7f), lamp(0.92f, 0.9f, 0.82f), tail(0.65f, 0.05f, 0.04f);
    auto body = [=](const glm::dvec3& p, const glm::dvec3& n) {
        const double hy = 0.5 * W, top = 0.5 * hb;
        if (n.x > 0.7) {  // front: headlights at the corners, grille, plate
            if (p.z > top - 0.25 && p.z < top - 0.06 && std::abs(p.y) > hy - 0.38 && std::abs(p.y) < hy - 0.08) return lamp;
            if (std::abs(p.y) < 0.32 && p.z > top - 0.3 && p.z < top - 0.08) return glm::vec3(0.06f);
            if (std::abs(p.y) < 0.25 && std::abs(p.z + 0.08) < 0.06) return glm::vec3(0.9f);
        }
        if (n.x < -0.7) {  // back: tail lights, plate
            if (p.z > top - 0.25 && p.z < top - 0.08 && std::abs(p.y) > hy - 0.35 && std::abs(p.y) < hy - 0.06) return tail;
            if (std::abs(p.y) < 0.25 && std::abs(p.z + 0.05) < 0.06) return glm::vec3(0.9f);
        }
        if (std::abs(n.y) > 0.7) {  // doors: seams and handles
            if (std::abs(p.x - 0.05 * L) < 0.006 || std::abs(p.x + 0.22 * L) < 0.006 || std::abs(p.x - 0.3 * L) < 0.006)
                return paint * 0.4f;
            if (std::abs(p.z - (top - 0.12)) < 0.02 && (std::abs(p.x + 0.14 * L) < 0.07 || std::abs(p.x - 0.14 * L) < 0.07))
                return chrome;
        }
        if (p.z < -top + 0.08) return glm::vec3(0.08f);  // sills, bumpers' lower edge
        return paint;
    };
    Material paint_m;
    paint_m.albedo = body;
    paint_m.gloss = 0.2f;
    paint_m.colour_noise = 0.02f;
    car.parts.push_back({make_rounded_box({0.5 * L, 0.5 * W, 0.5 * hb}, 0.14), Frame::at({0, 0, z0 + 0.5 * hb}), paint_m});

    // Cabin: glass all round with pillars, roof in paint.
    const double cab_len = type == 1 ? 0.46 * L : (type == 0 ? 0.55 * L : 0.6 * L), cab_x = type == 1 ? -0.06 * L : -0.1 * L;
    const glm::dvec2 bottom(0.5 * cab_len, 0.5 * W - 0.06), top(0.5 * cab_len - (type == 2 ? 0.25 : 0.45), 0.5 * W - 0.2);
    const double shift = type == 2 ? -0.1 : -0.12;
    auto cabin = [=](const glm::dvec3& p, const glm::dvec3& n) {
        if (n.z > 0.9) return paint;
        if (p.z < 0.06) return paint;  // waist line
        if (std::abs(n.y) > 0.6) {     // side windows with a B pillar
            if (std::abs(p.x - 0.1 * cab_len) < 0.05) return glm::vec3(0.05f);
            const double frac = (p.z - 0.06) / hc, edge = bottom.x - (bottom.x - top.x) * frac;
            if (std::abs(p.x - shift * frac) > edge - 0.08) return paint;  // A and C pillars
        }
        return glass;
    };
    Material cab_m;
    cab_m.albedo = cabin;
    cab_m.gloss = 0.3f;
    cab_m.colour_noise = 0.02f;
    car.parts.push_back({make_tapered_box(bottom, top, hc, {shift, 0.0}), Frame::at({cab_x, 0, z0 + hb - 0.01}), cab_m});

    // Wheels: tyre with a rim on the outer face.
    auto wheel = [=](const glm::dvec3& p, const glm::dvec3& n) {
        const double rho = std::hypot(p.x, p.y);
        if (std::abs(n.z) > 0.9 && rho < 0.62 * rw) {
            const double a = std::atan2(p.y, p.x);
            return (rho > 0.15 * rw && std::cos(5.0 * a) > 0.3) ? glm::vec3(0.15f) : chrome;
        }
        return glm::vec3(0.05f);
    };
    Material wheel_m;
    wheel_m.albedo = wheel;
    wheel_m.gloss = 0.05f;
    const double wx = 0.5 * L - (type == 0 ? 0.7 : 0.85), wy = 0.5 * W - 0.13, ww = 0.22;
    for (double sx : {-1.0, 1.0})
        for (double sy : {-1.0, 1.0}) {
            // Cylinder axis along y, its outer cap facing away from the car.
            const Frame f = Frame::at({sx * wx, sy * (wy - 0.5 * ww), rw}) * Frame::rotation({1, 0, 0}, -sy * 0.5 * kPi);
            car.parts.push_back({make_cylinder(rw, ww), f, wheel_m, 0.6});
        }
    // Mirrors, thin and sticking out; an antenna on some.
    Material mirror_m;
    mirror_m.albedo = plain(paint, 0.02f);
    mirror_m.gloss = 0.2f;
    for (double sy : {-1.0, 1.0})
        car.parts.push_back({make_rounded_box({0.05, 0.09, 0.055}, 0.02),
                             Frame::at({cab_x + bottom.x - 0.1, sy * (0.5 * W + 0.05), z0 + hb + 0.08}), mirror_m, 0.4});
    if (rng.chance(0.5)) {
        Material black;
        black.albedo = plain(glm::vec3(0.05f), 0.0f);
        black.aligned = 1.0f;
        car.parts.push_back({make_capsule(0.005, 0.35),
                             Frame::at({cab_x - bottom.x + 0.2, 0, z0 + hb + hc - 0.02}) * Frame::rotation({0, 1, 0}, -0.5),
                             black, 0.3});
    }
    return car;
}

}  // namespace pg::data::synth

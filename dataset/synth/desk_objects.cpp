// Desk objects. Sizes in metres; colours are albedos before the baked lighting.
#include "dataset/synth/desk_objects.h"

#include <cmath>

#include "dataset/synth/texture.h"

namespace pg::data::synth {
namespace {

Material mat(Albedo albedo, float gloss = 0.03f, float aligned = 0.0f) {
    Material m;
    m.albedo = std::move(albedo);
    m.gloss = gloss;
    m.aligned = aligned;
    return m;
}

Frame at(double x, double y, double z) { return Frame::at(glm::dvec3(x, y, z)); }
Frame turn(const glm::dvec3& axis, double angle) { return Frame::rotation(axis, angle); }
const glm::dvec3 kX(1, 0, 0), kY(0, 1, 0), kZ(0, 0, 1);

glm::vec3 tint(glm::vec3 c, float k) { return glm::clamp(c * k, glm::vec3(0.0f), glm::vec3(1.0f)); }

DeskObject mug(glm::vec3 colour, Rng& rng) {
    DeskObject o;
    const double R = rng.uniform(0.035, 0.045), H = rng.uniform(0.08, 0.105), wall = 0.004, floor = 0.007;
    const glm::vec3 band = tint(colour, 0.6f);
    const double band_z = rng.uniform(0.3, 0.7) * H;
    auto glaze = [=](const glm::dvec3& p, const glm::dvec3& n) {
        if (n.z > 0.9 && p.z > H - 1e-6) return glm::vec3(0.92f, 0.9f, 0.86f);  // rim
        return std::abs(p.z - band_z) < 0.006 ? band : colour;
    };
    o.parts.push_back({make_cylinder(R, H, R - wall, floor), Frame{}, mat(glaze, 0.08f)});
    if (rng.chance(0.6))  // coffee or tea
        o.parts.push_back({make_cylinder(R - wall, rng.uniform(0.5, 0.8) * H - floor), at(0, 0, floor),
                           mat(plain(glm::vec3(0.22f, 0.12f, 0.05f), 0.05f, 0.01), 0.1f)});
    // Handle: a half torus in the x-z plane whose ends sit inside the wall.
    o.parts.push_back({make_torus(0.3 * H, 0.0055, -0.5 * kPi, 0.5 * kPi), at(R - 0.002, 0, 0.5 * H) * turn(kX, 0.5 * kPi),
                       mat(plain(colour, 0.03f), 0.08f)});
    o.half = glm::dvec2(R);
    o.round = true;
    o.height = H;
    return o;
}

DeskObject book(glm::vec3 colour, Rng& rng) {
    DeskObject o;
    const glm::dvec3 half(rng.uniform(0.07, 0.12), rng.uniform(0.05, 0.085), rng.uniform(0.008, 0.022));
    const glm::vec3 pages(0.93f, 0.9f, 0.8f), title = hsv(float(rng.uniform()), 0.5f, 0.9f);
    const double band = rng.uniform(-0.5, 0.5) * half.x;
    auto cover = [=](const glm::dvec3& p, const glm::dvec3& n) {
        const bool spine = n.x < -0.9, board = std::abs(n.z) > 0.9;
        if (!spine && !board) return pages * (0.93f + 0.07f * float(std::sin(p.z * 2500.0)));  // page edges
        // The cover wraps the block: a thin margin of cover colour on the page sides too.
        if (board && std::abs(p.x - band) < 0.012) return title;
        return colour;
    };
    o.parts.push_back({make_box(half), at(0, 0, half.z), mat(cover, 0.04f)});
    o.half = glm::dvec2(half.x, half.y);
    o.height = 2 * half.z;
    o.flat_top = true;
    o.leans = true;
    return o;
}

DeskObject box(glm::vec3 colour, Rng& rng) {
    DeskObject o;
    const glm::dvec3 half(rng.uniform(0.045, 0.09), rng.uniform(0.04, 0.07), rng.uniform(0.025, 0.06));
    const glm::vec3 tape = tint(colour, 1.25f);
    const double r = rng.uniform(0.002, 0.006);
    auto cardboard = [=](const glm::dvec3& p, const glm::dvec3& n) {
        if (n.z > 0.5 && std::abs(p.y) < 0.012) return tape;
        return colour * (0.95f + 0.1f * value_noise(p * 150.0, 4));
    };
    o.parts.push_back({make_rounded_box(half, r), at(0, 0, half.z), mat(cardboard, 0.02f)});
    o.half = glm::dvec2(half.x, half.y);
    o.height = 2 * half.z;
    o.flat_top = true;
    return o;
}

DeskObject ball(glm::vec3 colour, Rng& rng) {
    DeskObject o;
    const double r = rng.uniform(0.03, 0.06);
    const glm::vec3 other = rng.chance(0.5) ? glm::vec3(0.92f, 0.92f, 0.9f) : tint(colour, 0.55f);
    const int segments = 2 * rng.between(2, 4);
    auto seg = [=](const glm::dvec3& p, const glm::dvec3&) {
        const double a = std::atan2(p.y, p.x) + kPi;
        return (int(a / (2 * kPi) * segments) % 2) ? other : colour;
    };
    o.parts.push_back({make_ellipsoid(glm::dvec3(r)), at(0, 0, r), mat(seg, 0.1f)});
    o.half = glm::dvec2(r);
    o.round = true;
    o.height = 2 * r;
    return o;
}

DeskObject bottle(glm::vec3 colour, Rng& rng) {
    DeskObject o;
    const double R = rng.uniform(0.028, 0.038), H = rng.uniform(0.13, 0.19), neck = 0.012;
    const glm::vec3 cap = hsv(float(rng.uniform()), 0.7f, 0.8f);
    const glm::vec3 label = tint(colour, 1.4f);
    auto body = [=](const glm::dvec3& p, const glm::dvec3&) {
        return p.z > 0.3 * H && p.z < 0.75 * H ? label : colour;
    };
    o.parts.push_back({make_cylinder(R, H), Frame{}, mat(body, 0.12f)});
    o.parts.push_back({make_cone(R, neck, 0.035), at(0, 0, H), mat(plain(colour, 0.03f), 0.12f)});
    o.parts.push_back({make_cylinder(neck, 0.02), at(0, 0, H + 0.035), mat(plain(colour, 0.03f), 0.12f)});
    o.parts.push_back({make_cylinder(neck + 0.002, 0.016), at(0, 0, H + 0.05), mat(plain(cap, 0.03f), 0.05f)});
    o.half = glm::dvec2(R);
    o.round = true;
    o.height = H + 0.066;
    return o;
}

DeskObject can(glm::vec3 colour, Rng& rng) {
    DeskObject o;
    const double R = 0.033, H = rng.chance(0.5) ? 0.115 : 0.165;
    const glm::vec3 stripe = rng.chance(0.5) ? glm::vec3(0.95f) : hsv(float(rng.uniform()), 0.8f, 0.85f);
    auto label = [=](const glm::dvec3& p, const glm::dvec3& n) {
        if (std::abs(n.z) > 0.9 || p.z > H - 0.008 || p.z < 0.006) return glm::vec3(0.75f, 0.76f, 0.78f);  // metal
        const double a = std::atan2(p.y, p.x);
        return std::abs(std::sin(3 * a + 20 * p.z)) < 0.25 ? stripe : colour;
    };
    o.parts.push_back({make_cylinder(R, H), Frame{}, mat(label, 0.15f)});
    o.half = glm::dvec2(R);
    o.round = true;
    o.height = H;
    return o;
}

DeskObject plant(glm::vec3 colour, Rng& rng) {
    DeskObject o;
    const double r0 = rng.uniform(0.035, 0.05), r1 = r0 * 1.3, h = rng.uniform(0.07, 0.1);
    auto pot = [=](const glm::dvec3& p, const glm::dvec3& n) {
        if (n.z > 0.9 && std::hypot(p.x, p.y) < r1 - 0.006) return glm::vec3(0.2f, 0.13f, 0.08f);  // soil
        return colour;
    };
    o.parts.push_back({make_cone(r0, r1, h), Frame{}, mat(pot, 0.03f)});
    const int leaves = rng.between(3, 5);
    const glm::vec3 green = hsv(float(rng.uniform(0.22, 0.36)), 0.65f, 0.45f);
    Material foliage = mat(plain(green, 0.2f, 0.01, rng.next()), 0.02f);
    foliage.fuzz = 0.5f;
    for (int i = 0; i < leaves; ++i) {
        const double a = 2 * kPi * i / leaves + rng.uniform(0, 1);
        const glm::dvec3 radii(rng.uniform(0.025, 0.04), rng.uniform(0.02, 0.03), rng.uniform(0.03, 0.05));
        o.parts.push_back({make_ellipsoid(radii), at(0.03 * std::cos(a), 0.03 * std::sin(a), h + radii.z * 0.8) * turn(kZ, a),
                           foliage});
    }
    o.half = glm::dvec2(r1 + 0.02);
    o.round = true;
    o.height = h + 0.09;
    return o;
}

DeskObject lamp(glm::vec3 colour, Rng& rng) {
    DeskObject o;
    const double pole = rng.uniform(0.22, 0.32), reach = rng.uniform(0.1, 0.16), tilt = rng.uniform(0.9, 1.3);
    const Material metal = mat(plain(colour, 0.03f), 0.15f);
    o.parts.push_back({make_cylinder(0.065, 0.018), Frame{}, metal});
    o.parts.push_back({make_capsule(0.007, pole), at(0, 0, 0.018), metal});
    // Arm: from the pole top, tilted towards +x.
    const glm::dvec3 top(0, 0, 0.018 + pole);
    o.parts.push_back({make_capsule(0.006, reach), Frame::at(top) * turn(kY, tilt), metal});
    const glm::dvec3 end = top + reach * glm::dvec3(std::sin(tilt), 0, std::cos(tilt));
    // Shade: a cone opening downwards under the arm's end.
    o.parts.push_back({make_cone(0.02, 0.065, 0.085), Frame::at(end + glm::dvec3(0, 0, 0.01)) * turn(kX, kPi),
                       mat(plain(tint(colour, 1.2f), 0.03f), 0.1f)});
    o.half = glm::dvec2(0.07);
    o.round = true;
    o.height = 0.018 + pole + 0.02;
    return o;
}

DeskObject laptop(glm::vec3 colour, Rng& rng) {
    DeskObject o;
    const glm::dvec3 base(rng.uniform(0.15, 0.175), rng.uniform(0.1, 0.12), 0.009);
    const double lid_t = 0.0035, open = rng.uniform(1.75, 2.0);  // radians from closed
    auto keys = [=](const glm::dvec3& p, const glm::dvec3& n) {
        if (n.z < 0.9) return colour;
        const bool deck = p.y > -base.y * 0.15 && std::abs(p.x) < base.x * 0.85 && p.y < base.y * 0.85;
        if (!deck) return std::abs(p.x) < 0.04 && p.y < -base.y * 0.3 && p.y > -base.y * 0.85 ? tint(colour, 0.8f) : colour;
        const bool gap = std::fmod(p.x + 1.0, 0.019) < 0.003 || std::fmod(p.y + 1.0, 0.019) < 0.003;
        return gap ? colour : glm::vec3(0.08f);
    };
    o.parts.push_back({make_rounded_box(base, 0.003), at(0, 0, base.z), mat(keys, 0.05f)});
    auto screen = [=](const glm::dvec3& p, const glm::dvec3& n) {
        if (n.z > -0.9) return colour;  // back of the lid (local +z), edges
        const bool glass = std::abs(p.x) < base.x - 0.012 && std::abs(p.y) < base.y - 0.012;
        if (!glass) return glm::vec3(0.05f);
        return glm::mix(glm::vec3(0.1f, 0.15f, 0.3f), glm::vec3(0.75f, 0.8f, 0.85f), float(p.y > 0.0 && p.x < 0.02));
    };
    // The lid hinges on the base's back edge (+y) and opens by `open` from lying on it.
    const Frame lid = at(0, base.y, 2 * base.z) * turn(kX, -open) * at(0, -base.y, lid_t);
    o.parts.push_back({make_box(glm::dvec3(base.x, base.y, lid_t)), lid, mat(screen, 0.1f)});
    o.half = glm::dvec2(base.x, base.y + 0.03);
    o.height = 2 * base.z + 2 * base.y * std::sin(open);
    return o;
}

DeskObject phone(glm::vec3 colour, Rng& rng) {
    DeskObject o;
    const glm::dvec3 half(0.037, 0.075, 0.0045);
    const bool face_up = rng.chance(0.6);
    auto skin = [=](const glm::dvec3& p, const glm::dvec3& n) {
        if (face_up && n.z > 0.9 && std::abs(p.x) < 0.033 && std::abs(p.y) < 0.068) return glm::vec3(0.04f, 0.05f, 0.07f);
        if (!face_up && n.z > 0.9 && std::hypot(p.x + 0.02, p.y - 0.055) < 0.01) return glm::vec3(0.1f);  // camera
        return colour;
    };
    o.parts.push_back({make_rounded_box(half, 0.004), at(0, 0, half.z), mat(skin, 0.12f)});
    o.half = glm::dvec2(half.x, half.y);
    o.height = 2 * half.z;
    o.flat_top = true;
    return o;
}

DeskObject headphones(glm::vec3 colour, Rng& rng) {
    DeskObject o;
    const double R = rng.uniform(0.07, 0.085), tube = 0.007;
    const Material plastic = mat(plain(colour, 0.04f), 0.08f);
    // Lying flat: the band a half ring, the cups standing at its ends.
    const double shift = -0.5 * R;  // centre the footprint
    o.parts.push_back({make_torus(R, tube, 0.0, kPi), at(0, shift, tube), plastic});
    for (double s : {-1.0, 1.0})
        o.parts.push_back({make_ellipsoid(glm::dvec3(0.02, 0.035, 0.04), 0.0), at(s * R, shift - 0.005, 0),
                           mat(plain(tint(colour, 0.5f), 0.05f), 0.05f)});
    o.half = glm::dvec2(R + 0.025, 0.5 * R + 0.04);
    o.height = 0.04;
    return o;
}

DeskObject toy(glm::vec3 colour, Rng& rng) {
    DeskObject o;
    const double s = rng.uniform(0.8, 1.2);
    const glm::vec3 skin = hsv(float(rng.uniform(0.05, 0.1)), 0.4f, 0.9f);
    o.parts.push_back({make_ellipsoid(s * glm::dvec3(0.028, 0.022, 0.04), -0.03 * s), at(0, 0, 0.03 * s),
                       mat(plain(colour, 0.04f), 0.05f)});
    o.parts.push_back({make_ellipsoid(glm::dvec3(0.022 * s)), at(0, 0, 0.09 * s), mat(plain(skin, 0.04f), 0.05f)});
    for (double side : {-1.0, 1.0})
        o.parts.push_back({make_capsule(0.007 * s, 0.035 * s), at(side * 0.026 * s, 0, 0.06 * s) * turn(kY, side * 2.6),
                           mat(plain(colour, 0.04f), 0.05f)});
    o.half = glm::dvec2(0.04 * s);
    o.round = true;
    o.height = 0.112 * s;
    return o;
}

DeskObject cube(glm::vec3 colour, Rng& rng) {
    DeskObject o;
    const double h = rng.uniform(0.025, 0.03);
    const glm::vec3 faces[6] = {colour, {0.95f, 0.95f, 0.95f}, {0.85f, 0.1f, 0.1f}, {0.1f, 0.3f, 0.8f}, {0.95f, 0.5f, 0.05f}, {0.1f, 0.6f, 0.2f}};
    const uint64_t seed = rng.next();
    auto grid = [=](const glm::dvec3& p, const glm::dvec3& n) {
        const double cell = 2 * h / 3;
        const glm::dvec3 q = (p + glm::dvec3(h)) / cell;
        const glm::dvec3 f = q - glm::floor(q);
        const int axis = std::abs(n.x) > 0.7 ? 0 : (std::abs(n.y) > 0.7 ? 1 : 2);
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        if (f[u] < 0.08 || f[u] > 0.92 || f[v] < 0.08 || f[v] > 0.92) return glm::vec3(0.03f);
        const uint64_t k = mix64(seed + uint64_t(std::floor(q[u])) * 3 + uint64_t(std::floor(q[v])) * 11 + uint64_t(axis) * 97);
        return faces[k % 6];
    };
    o.parts.push_back({make_rounded_box(glm::dvec3(h), 0.002), at(0, 0, h), mat(grid, 0.08f)});
    o.half = glm::dvec2(h);
    o.height = 2 * h;
    o.flat_top = true;
    return o;
}

DeskObject tape(glm::vec3 colour, Rng& rng) {
    DeskObject o;
    const double R = rng.uniform(0.04, 0.055), w = rng.uniform(0.018, 0.025);
    o.parts.push_back({make_cylinder(R, w, R - 0.012), Frame{}, mat(stripes(colour, tint(colour, 0.85f), 0.002, kZ), 0.1f)});
    o.half = glm::dvec2(R);
    o.round = true;
    o.height = w;
    return o;
}

DeskObject mouse(glm::vec3 colour, Rng& rng) {
    DeskObject o;
    const glm::dvec3 r(0.03, 0.055, 0.02 * rng.uniform(1.0, 1.3));
    auto shell = [=](const glm::dvec3& p, const glm::dvec3&) {
        if (p.y > 0.012 && std::abs(p.x) < 0.0015) return glm::vec3(0.05f);  // button split
        return colour;
    };
    o.parts.push_back({make_ellipsoid(r, 0.0), Frame{}, mat(shell, 0.1f)});
    o.half = glm::dvec2(r.x, r.y);
    o.height = r.z;
    return o;
}

DeskObject pencil_cup(glm::vec3 colour, Rng& rng) {
    DeskObject o;
    const double R = rng.uniform(0.035, 0.045), H = rng.uniform(0.09, 0.11);
    o.parts.push_back({make_cylinder(R, H, R - 0.003, 0.006), Frame{}, mat(checker(colour, glm::vec3(0.1f), 0.012), 0.05f)});
    const int pens = rng.between(3, 5);
    for (int i = 0; i < pens; ++i) {
        const double a = 2 * kPi * i / pens + rng.uniform(0, 0.5), lean = rng.uniform(0.12, 0.25);
        const glm::vec3 c = hsv(float(rng.uniform()), 0.7f, 0.75f);
        // From a point on the floor near the wall opposite the lean, leaning outwards.
        const glm::dvec3 foot(-0.5 * R * std::cos(a), -0.5 * R * std::sin(a), 0.006 + 0.0045);
        const Frame f = Frame::at(foot) * turn(glm::dvec3(-std::sin(a), std::cos(a), 0), lean);
        o.parts.push_back({make_capsule(0.0045, rng.uniform(0.12, 0.15)), f, mat(plain(c, 0.03f), 0.08f, 1.0f)});
    }
    o.half = glm::dvec2(R);
    o.round = true;
    o.height = H + 0.05;
    return o;
}

}  // namespace

const char* desk_kind_name(DeskKind k) {
    static const char* names[kDeskKinds] = {"mug", "book", "box", "ball", "bottle", "can", "plant", "lamp",
                                            "laptop", "phone", "headphones", "toy", "cube", "tape", "mouse", "pencil_cup"};
    return names[int(k)];
}

int desk_kind_class(DeskKind k) { return int(k) + 1; }

DeskObject make_desk_object(DeskKind kind, glm::vec3 colour, Rng& rng) {
    DeskObject o;
    switch (kind) {
        case DeskKind::Mug: o = mug(colour, rng); break;
        case DeskKind::Book: o = book(colour, rng); break;
        case DeskKind::Box: o = box(colour, rng); break;
        case DeskKind::Ball: o = ball(colour, rng); break;
        case DeskKind::Bottle: o = bottle(colour, rng); break;
        case DeskKind::Can: o = can(colour, rng); break;
        case DeskKind::Plant: o = plant(colour, rng); break;
        case DeskKind::Lamp: o = lamp(colour, rng); break;
        case DeskKind::Laptop: o = laptop(colour, rng); break;
        case DeskKind::Phone: o = phone(colour, rng); break;
        case DeskKind::Headphones: o = headphones(colour, rng); break;
        case DeskKind::Toy: o = toy(colour, rng); break;
        case DeskKind::Cube: o = cube(colour, rng); break;
        case DeskKind::Tape: o = tape(colour, rng); break;
        case DeskKind::Mouse: o = mouse(colour, rng); break;
        case DeskKind::PencilCup: o = pencil_cup(colour, rng); break;
    }
    o.kind = kind;
    return o;
}

}  // namespace pg::data::synth

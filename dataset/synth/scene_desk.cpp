// Desk suite: 7-10 objects on a wooden table in a room. Objects touch, stand on each other
// and lean against each other; neighbours often share a colour; papers, sticky notes, pens
// and a cable lie around them as background.
#include <cmath>

#include "dataset/synth/desk_objects.h"
#include "dataset/synth/suites.h"
#include "dataset/synth/texture.h"

namespace pg::data::synth {
namespace {

constexpr double kTableX = 0.75, kTableY = 0.45, kTableZ = 0.03, kFloor = -0.75, kCeiling = 1.75, kRoom = 2.5;
constexpr double kZoneX = 0.5, kZoneY = 0.32;  // where objects stand, inside the views
constexpr double kRoomSigma = 0.035, kTableSigma = 0.005, kClutterSigma = 0.0022;

Material mat(Albedo a, float gloss = 0.02f, float aligned = 0.0f) {
    Material m;
    m.albedo = std::move(a);
    m.gloss = gloss;
    m.aligned = aligned;
    return m;
}

Shape& background(Layout& L, PrimitivePtr prim, const Frame& f, Albedo a, double sigma, bool shadows = true) {
    Shape& s = L.add(std::move(prim), f, mat(std::move(a)), sigma);
    s.casts_shadow = shadows;
    return s;
}

void add_room(Layout& L, Rng& rng) {
    const glm::vec3 wall = hsv(float(rng.uniform(0.05, 0.15)), float(rng.uniform(0.05, 0.2)), float(rng.uniform(0.75, 0.9)));
    const double h = kCeiling - kFloor, t = 0.05;
    background(L, make_box({kRoom, kRoom, t}), Frame::at({0, 0, kFloor - t}),
               checker(glm::vec3(0.5f, 0.48f, 0.45f), glm::vec3(0.42f, 0.4f, 0.38f), 0.5), kRoomSigma, false);
    background(L, make_box({kRoom, kRoom, t}), Frame::at({0, 0, kCeiling + t}), plain(glm::vec3(0.9f), 0.03f, 0.5),
               kRoomSigma, false);
    const uint64_t seed = rng.next();
    auto walls = [=](const glm::dvec3& p, const glm::dvec3& n) {
        const double u = glm::dot(p, glm::dvec3(-n.y, n.x, 0.0));
        if (p.z < kFloor + 0.1) return glm::vec3(0.3f);  // skirting
        if (n.y < -0.9 && std::abs(u) < 0.8 && p.z > 0.1 && p.z < 1.2)  // a window onto a bright sky
            return std::abs(u) < 0.02 || std::abs(p.z - 0.65) < 0.02 ? glm::vec3(0.9f) : glm::vec3(0.7f, 0.82f, 0.95f);
        if (n.x > 0.9 && u > -0.4 && u < 0.4 && p.z > -0.3 && p.z < 0.3)  // a picture
            return hsv(float(fbm(p * 6.0, 3, seed)), 0.6f, 0.6f);
        if (n.y > 0.9 && u > 0.5 && u < 1.4 && p.z < 1.3) return glm::vec3(0.45f, 0.3f, 0.18f);  // door
        return wall * (0.92f + 0.08f * float(std::sin(p.z * 1.3 + u)));
    };
    for (int w = 0; w < 4; ++w) {
        const double a = 0.5 * kPi * w;
        const glm::dvec3 out(std::cos(a), std::sin(a), 0.0);
        background(L, make_box({t, kRoom, 0.5 * h}), Frame::at(out * (kRoom + t) + glm::dvec3(0, 0, kFloor + 0.5 * h)) *
                                                        Frame::rotation({0, 0, 1}, a),
                   walls, kRoomSigma, false);
    }
    // A shelf with books against the wall behind the door.
    const glm::dvec3 shelf(-kRoom + 0.2, 0.6, kFloor);
    const glm::vec3 shelf_colour(0.45f, 0.32f, 0.2f);
    for (int k = 0; k < 4; ++k)
        background(L, make_box({0.18, 0.5, 0.012}), Frame::at(shelf + glm::dvec3(0, 0, 0.3 + 0.35 * k)), plain(shelf_colour),
                   0.012);
    for (int k = 0; k < 10; ++k) {
        const double hh = rng.uniform(0.09, 0.13), ww = rng.uniform(0.012, 0.025);
        background(L, make_box({0.12, ww, hh}),
                   Frame::at(shelf + glm::dvec3(0.02, -0.45 + 0.09 * k, 0.3 + 0.35 * (k % 3) + 0.012 + hh)),
                   plain(hsv(float(rng.uniform()), 0.5f, 0.5f)), 0.008);
    }
}

void add_table(Layout& L, Rng& rng) {
    const glm::vec3 light = hsv(float(rng.uniform(0.06, 0.1)), float(rng.uniform(0.4, 0.6)), float(rng.uniform(0.55, 0.75)));
    Material top = mat(wood(light, light * 0.6f, rng.uniform(0.012, 0.025), rng.next()), 0.03f, 0.8f);
    L.add(make_box({kTableX, kTableY, kTableZ / 2}), Frame::at({0, 0, -kTableZ / 2}), top, kTableSigma);
    for (double sx : {-1.0, 1.0})
        for (double sy : {-1.0, 1.0}) {
            const double h = -kFloor - kTableZ;
            L.add(make_box({0.025, 0.025, h / 2}), Frame::at({sx * (kTableX - 0.07), sy * (kTableY - 0.07), kFloor + h / 2}),
                  mat(plain(light * 0.7f)), 0.01);
        }
}

// A placed object's footprint on its support.
struct Placed {
    glm::dvec2 c{0.0};
    double yaw = 0;
    glm::dvec2 half{0.0};
    bool round = false;
    double z0 = 0, top = 0;
    bool flat_top = false, carries = false;
    glm::vec3 colour{0.5f};
};

double support(const Placed& p, glm::dvec2 u) {
    if (p.round) return p.half.x;
    const glm::dvec2 ax(std::cos(p.yaw), std::sin(p.yaw)), ay(-ax.y, ax.x);
    return std::abs(p.half.x * glm::dot(u, ax)) + std::abs(p.half.y * glm::dot(u, ay));
}

// Separating-axis test on footprints (touching counts as separated).
bool separated(const Placed& a, const Placed& b) {
    const glm::dvec2 d = b.c - a.c;
    std::vector<glm::dvec2> axes;
    if (glm::length(d) > 1e-9) axes.push_back(glm::normalize(d));
    for (const Placed* p : {&a, &b})
        if (!p->round) {
            axes.emplace_back(std::cos(p->yaw), std::sin(p->yaw));
            axes.emplace_back(-std::sin(p->yaw), std::cos(p->yaw));
        }
    for (const glm::dvec2& u : axes)
        if (std::abs(glm::dot(d, u)) >= support(a, u) + support(b, u) - 1e-5) return true;
    return false;
}

bool in_zone(const Placed& p) {
    return std::abs(p.c.x) + support(p, {1, 0}) <= kZoneX && std::abs(p.c.y) + support(p, {0, 1}) <= kZoneY;
}

bool free_on_table(const Placed& p, const std::vector<Placed>& placed) {
    if (!in_zone(p)) return false;
    for (const Placed& q : placed)
        if (q.z0 == 0.0 && !separated(p, q)) return false;
    return true;
}

glm::vec3 pick_colour(Rng& rng, const std::vector<Placed>& placed) {
    // Neighbours often share a colour family: segmentation by colour must fail.
    if (!placed.empty() && rng.chance(0.45)) {
        const glm::vec3 c = placed[size_t(rng.below(int(placed.size())))].colour;
        return glm::clamp(c * glm::vec3(float(rng.uniform(0.9, 1.1)), float(rng.uniform(0.9, 1.1)), float(rng.uniform(0.9, 1.1))),
                          glm::vec3(0.02f), glm::vec3(0.98f));
    }
    return hsv(float(rng.uniform()), float(rng.uniform(0.25, 0.85)), float(rng.uniform(0.35, 0.9)));
}

DeskKind pick_kind(Rng& rng, std::vector<int>& used) {
    static const int weights[kDeskKinds] = {4, 5, 4, 2, 2, 2, 2, 1, 1, 2, 1, 2, 2, 1, 1, 1};
    for (int tries = 0; tries < 100; ++tries) {
        int total = 0;
        for (int w : weights) total += w;
        int r = rng.below(total), k = 0;
        while (r >= weights[k]) r -= weights[k++];
        const int limit = (k == int(DeskKind::Book) || k == int(DeskKind::Mug) || k == int(DeskKind::Box)) ? 3 : 1;
        if (used[size_t(k)] < limit) {
            ++used[size_t(k)];
            return DeskKind(k);
        }
    }
    return DeskKind::Box;
}

// A book standing on its bottom edge, tilted by theta against the neighbour q from the -u side.
bool lean_book(Layout& L, const DeskObject& o, const Placed& q, Rng& rng, std::vector<Placed>& placed, int id, int cls,
               double sigma, glm::vec3 colour) {
    const double hx = o.half.x, hz = 0.5 * o.height;  // standing: its length is the height
    if (q.top - q.z0 < 0.05 || q.z0 != 0.0) return false;
    const double angle = rng.uniform(0.0, 2.0 * kPi), theta = rng.uniform(0.2, 0.45);
    const glm::dvec2 u(std::cos(angle), std::sin(angle));
    const double reach = std::min(2.0 * hx * std::sin(theta), q.top * std::tan(theta));
    const glm::dvec2 face = q.c - support(q, u) * u;
    const glm::dvec2 pivot = face - reach * u;
    Placed p;
    p.c = pivot - 0.5 * (2.0 * hz) * u + 0.5 * reach * u;
    p.yaw = angle;
    p.half = glm::dvec2(0.5 * (reach + 2.0 * hz), o.half.y);
    p.colour = colour;
    p.top = 2.0 * hx * std::cos(theta);
    std::vector<Placed> others;
    for (const Placed& r : placed)
        if (&r != &q) others.push_back(r);
    if (!free_on_table(p, others)) return false;
    const glm::dvec3 up(0, 0, 1), u3(u, 0.0), v3 = glm::cross(u3, up);
    const Frame stand{glm::dmat3(up, v3, u3), glm::dvec3(pivot, 0.0) - hz * u3 + hx * up};  // book x up, z along u
    const glm::dvec3 P(pivot, 0.0);
    const Frame tilt = Frame::at(P) * Frame::rotation(glm::cross(up, u3), theta) * Frame::at(-P);
    // Parts are modelled lying with their base at z = 0: undo that before standing up.
    L.add_parts(o.parts, tilt * stand * Frame::at({0, 0, -hz}), sigma, id, cls);
    placed.push_back(p);
    return true;
}

void add_objects(Layout& L, Rng& rng, std::vector<Placed>& placed) {
    const int count = rng.between(7, 10);
    std::vector<int> used(kDeskKinds, 0);
    // Until `count` stand (an object that finds no place is dropped and another drawn).
    for (int attempt = 0; int(L.instances.size()) < count && attempt < 4 * count; ++attempt) {
        const DeskKind kind = pick_kind(rng, used);
        const glm::vec3 colour = pick_colour(rng, placed);
        const DeskObject o = make_desk_object(kind, colour, rng);
        const int cls = desk_kind_class(kind);
        const int id = int(L.instances.size()) + 1;
        const double size = std::max({2.0 * o.half.x, 2.0 * o.half.y, o.height});
        const double sigma = std::clamp(0.025 * size, 0.0012, 0.003);
        const double radius = o.round ? o.half.x : glm::length(o.half);
        bool done = false;

        // Stand on a flat top that is free and large enough.
        if (!placed.empty() && rng.chance(0.3)) {
            const size_t k = size_t(rng.below(int(placed.size())));
            Placed& base = placed[k];
            const double room = std::min(base.half.x, base.half.y) - radius;
            if (base.flat_top && !base.carries && room >= 0.0) {
                Placed p;
                p.c = base.c + room * rng.uniform(0.0, 0.8) * glm::dvec2(rng.normal(), rng.normal()) / 2.0;
                p.yaw = base.yaw + 0.3 * rng.normal();
                p.half = o.half;
                p.round = o.round;
                p.z0 = base.top;
                p.top = base.top + o.height;
                p.flat_top = o.flat_top;
                p.colour = colour;
                if (glm::length(p.c - base.c) <= room) {
                    base.carries = true;
                    L.add_parts(o.parts, Frame::at(glm::dvec3(p.c, p.z0)) * Frame::rotation({0, 0, 1}, p.yaw), sigma, id, cls);
                    placed.push_back(p);
                    done = true;
                }
            }
        }
        if (!done && o.leans && !placed.empty() && rng.chance(0.45))
            done = lean_book(L, o, placed[size_t(rng.below(int(placed.size())))], rng, placed, id, cls, sigma, colour);
        for (int tries = 0; !done && tries < 300; ++tries) {
            Placed p;
            p.half = o.half;
            p.round = o.round;
            p.top = o.height;
            p.flat_top = o.flat_top;
            p.colour = colour;
            p.yaw = rng.uniform(0.0, 2.0 * kPi);
            if (!placed.empty() && tries < 200 && rng.chance(0.7)) {
                // Touching a neighbour on the table: along one of its axes, or any direction when round.
                const Placed& q = placed[size_t(rng.below(int(placed.size())))];
                if (q.z0 != 0.0) continue;
                double a = rng.uniform(0.0, 2.0 * kPi);
                if (!q.round) {
                    a = q.yaw + 0.5 * kPi * rng.below(4);
                    p.yaw = q.yaw + 0.5 * kPi * rng.below(2) + 0.05 * rng.normal();
                }
                const glm::dvec2 u(std::cos(a), std::sin(a));
                p.c = q.c + (support(q, u) + support(p, -u) + rng.uniform(0.0, 0.002)) * u;
            } else {
                p.c = glm::dvec2(rng.uniform(-kZoneX, kZoneX), rng.uniform(-kZoneY, kZoneY));
            }
            if (!free_on_table(p, placed)) continue;
            L.add_parts(o.parts, Frame::at(glm::dvec3(p.c, 0.0)) * Frame::rotation({0, 0, 1}, p.yaw), sigma, id, cls);
            placed.push_back(p);
            done = true;
        }
        if (done) L.add_instance(cls, std::string(desk_kind_name(kind)) + "_" + std::to_string(id));
    }
}

void add_clutter(Layout& L, Rng& rng, const std::vector<Placed>& placed) {
    const int papers = rng.between(1, 3);
    for (int i = 0; i < papers; ++i) {
        // All on the table top, each a little thicker: overlaps never tie.
        const glm::dvec3 half(0.105, 0.1485, 0.0002 + 0.0001 * i);
        const glm::dvec2 c(rng.uniform(-0.6, 0.6), rng.uniform(-0.3, 0.3));
        L.add(make_box(half), Frame::at({c, half.z}) * Frame::rotation({0, 0, 1}, rng.uniform(0, 2 * kPi)),
              mat(paper(glm::vec3(0.94f, 0.94f, 0.91f), {0.08, 0.12}, 0.006, rng.next()), 0.01f, 0.5f), kClutterSigma * 1.5);
    }
    // Pens and sticky notes where nothing stands.
    const int small = rng.between(2, 5);
    for (int i = 0, tries = 0; i < small && tries < 200; ++tries) {
        Placed p;
        p.c = glm::dvec2(rng.uniform(-0.65, 0.65), rng.uniform(-0.38, 0.38));
        p.yaw = rng.uniform(0, 2 * kPi);
        const bool pen = rng.chance(0.6);
        p.half = pen ? glm::dvec2(0.075, 0.005) : glm::dvec2(0.038, 0.038);
        bool ok = true;
        for (const Placed& q : placed) ok = ok && separated(p, q);
        if (!ok) continue;
        const Frame f = Frame::at({p.c, 0.0}) * Frame::rotation({0, 0, 1}, p.yaw);
        if (pen)
            L.add(make_capsule(0.0045, 0.14), f * Frame::at({-0.07, 0, 0.0045}) * Frame::rotation({0, 1, 0}, 0.5 * kPi),
                  mat(plain(hsv(float(rng.uniform()), 0.6f, 0.7f)), 0.08f, 1.0f), kClutterSigma);
        else
            L.add(make_box({0.038, 0.038, 0.0005}), f * Frame::at({0, 0, 0.0005}),
                  mat(plain(hsv(float(rng.uniform(0.1, 0.2)), 0.6f, 0.95f), 0.03f)), kClutterSigma * 1.5);
        ++i;
    }
    // A cable from the back edge, then wandering along the back of the table between the
    // objects' zone and the edge: capsules joined end to end, lying on the top.
    const double r = 0.0025, band = 0.5 * (kZoneY + kTableY), wiggle = 0.4 * (kTableY - kZoneY);
    const double dir = rng.sign(), phase = rng.uniform(0, 2 * kPi), freq = rng.uniform(8.0, 14.0);
    const double x0 = rng.uniform(-0.4, 0.4);
    std::vector<glm::dvec2> path = {{x0, kTableY - 0.001}};
    for (int k = 1; k < 60; ++k) {
        const double x = x0 + dir * 0.025 * k;
        if (std::abs(x) > kTableX - 0.02) break;
        path.emplace_back(x, band + wiggle * std::sin(phase + freq * (x - x0)) * std::min(1.0, 0.3 * k));
    }
    for (size_t k = 0; k + 1 < path.size(); ++k) {
        Placed seg;
        seg.c = 0.5 * (path[k] + path[k + 1]);
        seg.yaw = std::atan2(path[k + 1].y - path[k].y, path[k + 1].x - path[k].x);
        seg.half = glm::dvec2(0.5 * glm::length(path[k + 1] - path[k]) + r, r);
        bool ok = true;
        for (const Placed& o : placed) ok = ok && (o.z0 > 0.0 || separated(seg, o));
        if (!ok) break;
        const glm::dvec3 a3(path[k], r), b3(path[k + 1], r);
        L.add(make_capsule(r, glm::length(b3 - a3)), Frame::axes(b3 - a3, {0, 0, 1}, a3),
              mat(plain(glm::vec3(0.08f), 0.02f), 0.1f, 1.0f), kClutterSigma);
    }
}

}  // namespace

std::vector<ClassInfo> desk_classes() {
    std::vector<ClassInfo> c = {{0, "background"}};
    for (int k = 0; k < kDeskKinds; ++k) c.push_back({desk_kind_class(DeskKind(k)), desk_kind_name(DeskKind(k))});
    return c;
}

Layout build_desk(uint64_t seed) {
    Rng rng(seed);
    Layout L;
    L.fixed_up = true;
    L.default_sh_degree = 3;
    L.classes = desk_classes();
    add_room(L, rng);
    add_table(L, rng);
    std::vector<Placed> placed;
    add_objects(L, rng, placed);
    add_clutter(L, rng, placed);

    glm::dvec2 centre(0.0);
    for (const Placed& p : placed) centre += p.c / double(placed.size());
    L.orbit.target = glm::dvec3(centre, 0.05);
    L.orbit.radius = 0.95;
    L.orbit.elevations = {22, 40, 60};
    L.orbit.radius_jitter = 0.06;
    L.orbit.target_jitter = 0.02;
    L.orbit.fov_x = 60;
    L.orbit.default_count = 96;
    L.light.sun = glm::normalize(glm::dvec3(0.25, 0.35, 1.0));
    L.light.ambient = 0.55f;
    L.light.direct = 0.45f;
    L.light.shadow = 0.45f;
    L.light.sky = 0.06f;
    L.floater_region = Aabb{glm::dvec3(-0.9, -0.7, 0.02), glm::dvec3(0.9, 0.7, 0.6)};
    L.floater_sigma = 0.004;
    return L;
}

}  // namespace pg::data::synth

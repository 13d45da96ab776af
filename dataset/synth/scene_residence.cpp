// Residence suite: 7-10 houses along a winding street on rolling terrain, some terraced
// (sharing a wall and a colour scheme), with garden trees whose crowns overlap the roofs,
// hedges and parked cars as background.
#include <cmath>

#include "dataset/synth/buildings.h"
#include "dataset/synth/suites.h"
#include "dataset/synth/texture.h"
#include "dataset/synth/vegetation.h"
#include "dataset/synth/vehicle.h"

namespace pg::data::synth {
namespace {

constexpr double kTerrain = 320.0;
constexpr int kGrid = 129;
constexpr double kHouseSigma = 0.11, kGroundSigma = 0.7, kTreeSigma = 0.2;

struct Plot {
    glm::dvec2 c;
    double yaw;
    glm::dvec2 half;  // footprint half extents (house axes)
    double ground;
};

// The street's centre line y(x) and its direction.
struct Street {
    double amp, freq, phase;
    double y(double x) const { return amp * std::sin(freq * x + phase); }
    double slope(double x) const { return amp * freq * std::cos(freq * x + phase); }
};

double rough_height(const glm::dvec2& p, uint64_t seed) {
    return 7.0 * (fbm(glm::dvec3(p / 140.0, 0.5), 4, seed) - 0.5) + 1.2 * (fbm(glm::dvec3(p / 25.0, 3.5), 2, seed + 9) - 0.5);
}

bool in_plot(const Plot& p, const glm::dvec2& q, double margin) {
    const glm::dvec2 d = q - p.c, ax(std::cos(p.yaw), std::sin(p.yaw)), ay(-ax.y, ax.x);
    return std::abs(glm::dot(d, ax)) < p.half.x + margin && std::abs(glm::dot(d, ay)) < p.half.y + margin;
}

double plot_distance(const Plot& p, const glm::dvec2& q) {
    const glm::dvec2 d = q - p.c, ax(std::cos(p.yaw), std::sin(p.yaw)), ay(-ax.y, ax.x);
    const double dx = std::max(0.0, std::abs(glm::dot(d, ax)) - p.half.x), dy = std::max(0.0, std::abs(glm::dot(d, ay)) - p.half.y);
    return std::hypot(dx, dy);
}

Material mat(Albedo a) {
    Material m;
    m.albedo = std::move(a);
    m.gloss = 0.02f;
    m.colour_noise = 0.06f;
    return m;
}

}  // namespace

std::vector<ClassInfo> residence_classes() { return {{0, "background"}, {1, "house"}}; }

Layout build_residence(uint64_t seed) {
    Rng rng(seed);
    Layout L;
    L.default_sh_degree = 1;
    L.classes = residence_classes();
    const uint64_t ground_seed = rng.next();
    const Street street{rng.uniform(3.0, 8.0), rng.uniform(0.02, 0.04), rng.uniform(0, 6.3)};

    // Houses on both sides of the street, facing it; runs of two or three share walls.
    const int count = rng.between(7, 10);
    std::vector<Plot> plots;
    const glm::vec3 walls[] = {{0.9f, 0.88f, 0.82f}, {0.85f, 0.78f, 0.62f}, {0.7f, 0.42f, 0.32f}, {0.75f, 0.75f, 0.72f},
                               {0.82f, 0.72f, 0.55f}, {0.6f, 0.62f, 0.58f}};
    const glm::vec3 roofs[] = {{0.25f, 0.24f, 0.25f}, {0.55f, 0.25f, 0.15f}, {0.35f, 0.22f, 0.16f}, {0.3f, 0.33f, 0.38f}};
    double cursor[2] = {-6.0 * count / 2.0 - rng.uniform(0.0, 6.0), -6.0 * count / 2.0 - rng.uniform(0.0, 6.0)};
    int made = 0;
    HouseSpec previous;
    bool attach = false;
    int side = 0;
    while (made < count) {
        HouseSpec h;
        if (attach) {  // terraced: same scheme, shared wall
            h = previous;
            h.width = rng.uniform(6.5, 9.0);
            h.garage = 0;
            h.chimney = rng.chance(0.5);
            h.seed = rng.next();
        } else {
            side = rng.below(2);
            h.width = rng.uniform(7.5, 11.5);
            h.depth = rng.uniform(7.5, 10.5);
            h.storeys = rng.chance(0.7) ? 2 : 1;
            h.roof = RoofKind(rng.below(10) < 5 ? 0 : (rng.below(10) < 8 ? 1 : 2));
            h.pitch = rng.uniform(0.5, 0.9);
            h.wall = walls[rng.below(6)];
            h.roof_colour = roofs[rng.below(4)];
            h.bricks = h.wall.x > 0.65f && h.wall.y < 0.5f;
            h.chimney = rng.chance(0.6);
            h.garage = rng.chance(0.3) ? (rng.chance(0.5) ? 1 : -1) : 0;
            h.seed = rng.next();
            cursor[side] += rng.uniform(2.0, 6.0);
        }
        const double span = house_span(h);
        const double x_mid = cursor[side] + 0.5 * span;
        const double sign = side == 0 ? 1.0 : -1.0;
        const double setback = 3.5 + 4.0 + rng.uniform(0.0, 2.5) * (attach ? 0.0 : 1.0) + 0.5 * h.depth;
        const double heading = std::atan(street.slope(x_mid));
        const glm::dvec2 along(std::cos(heading), std::sin(heading)), across(-along.y, along.x);
        Plot p;
        p.c = glm::dvec2(x_mid, street.y(x_mid)) + sign * setback * across;
        p.yaw = heading + (side == 0 ? 0.0 : kPi);
        p.half = glm::dvec2(0.5 * span, 0.5 * h.depth);
        p.ground = rough_height(p.c, ground_seed);
        // Garage offset: the house body is centred on its own width.
        const double body_shift = h.garage == 0 ? 0.0 : -h.garage * 1.7;
        const Frame f = Frame::at({p.c, p.ground}) * Frame::rotation({0, 0, 1}, p.yaw) * Frame::at({body_shift, 0, 0});
        const int id = L.add_instance(1, "house_" + std::to_string(made + 1));
        L.add_parts(make_house(h), f, kHouseSigma, id, 1);
        plots.push_back(p);
        cursor[side] += span;
        previous = h;
        ++made;
        attach = attach ? rng.chance(0.3) : rng.chance(0.35);  // runs of two, sometimes three
    }

    // Terrain, levelled under each house and along the street.
    std::vector<double> heights(size_t(kGrid) * kGrid);
    const double cell = kTerrain / (kGrid - 1);
    for (int j = 0; j < kGrid; ++j)
        for (int i = 0; i < kGrid; ++i) {
            const glm::dvec2 q(-0.5 * kTerrain + i * cell, -0.5 * kTerrain + j * cell);
            double h = rough_height(q, ground_seed);
            for (const Plot& p : plots) {
                const double w = std::clamp(1.0 - (plot_distance(p, q) - 2.0) / 8.0, 0.0, 1.0);
                h = h + (p.ground - h) * w * w * (3.0 - 2.0 * w);
            }
            heights[size_t(j) * kGrid + size_t(i)] = h;
        }
    std::vector<Plot> drives = plots;
    const Albedo lawn = grass(glm::vec3(0.28f, 0.42f, 0.16f), ground_seed, 6.0);
    const Albedo tarmac = asphalt(glm::vec3(0.27f), ground_seed + 1);
    auto ground = [=](const glm::dvec3& p, const glm::dvec3& n) {
        const double off = std::abs(p.y - street.y(p.x));
        if (off < 3.5) return std::abs(off) < 0.08 && std::fmod(p.x + 1000.0, 6.0) < 3.0 ? glm::vec3(0.85f) : tarmac(p, n);
        if (off < 5.0) return glm::vec3(0.55f, 0.54f, 0.5f);  // pavement
        for (const Plot& d : drives)
            if (in_plot(d, glm::dvec2(p), 2.5)) return glm::vec3(0.45f, 0.42f, 0.38f);  // paths and yards
        return lawn(p, n);
    };
    L.add(make_heightfield(kGrid, kGrid, kTerrain, kTerrain, heights, -20.0), Frame{}, mat(ground), kGroundSigma);

    // Trees: some right beside houses so their crowns overlap roofs, others in gardens.
    const int trees = rng.between(25, 40);
    auto terrain_at = [&](const glm::dvec2& q) { return rough_height(q, ground_seed); };
    for (int k = 0, tries = 0; k < trees && tries < 2000; ++tries) {
        glm::dvec2 q;
        if (k < count) {
            const Plot& p = plots[size_t(rng.below(int(plots.size())))];
            const glm::dvec2 ax(std::cos(p.yaw), std::sin(p.yaw)), ay(-ax.y, ax.x);
            q = p.c + rng.sign() * (p.half.x + rng.uniform(1.0, 3.0)) * ax + rng.uniform(-1.0, 1.0) * p.half.y * ay;
        } else {
            q = glm::dvec2(rng.uniform(-60.0, 60.0), rng.uniform(-50.0, 50.0));
        }
        if (std::abs(q.y - street.y(q.x)) < 5.5) continue;
        bool clear = true;
        for (const Plot& p : plots) clear = clear && !in_plot(p, q, 0.6);
        if (!clear) continue;
        double ground_h = terrain_at(q);
        for (const Plot& p : plots) {
            const double w = std::clamp(1.0 - (plot_distance(p, q) - 2.0) / 8.0, 0.0, 1.0);
            ground_h = ground_h + (p.ground - ground_h) * w * w * (3.0 - 2.0 * w);
        }
        const Frame f = Frame::at({q, ground_h - 0.3}) * Frame::rotation({0, 0, 1}, rng.uniform(0, 6.3));
        for (const Part& p : make_tree(rng, rng.uniform(7.0, 13.0), rng.chance(0.25)))
            L.add(p.prim, f * p.frame, p.material, kTreeSigma * p.sigma_scale);
        ++k;
    }
    // Hedges along some plot fronts and cars on some drives (background).
    for (const Plot& p : plots) {
        const glm::dvec2 ax(std::cos(p.yaw), std::sin(p.yaw)), ay(-ax.y, ax.x);
        if (rng.chance(0.5)) {
            const glm::dvec2 q = p.c - (p.half.y + 2.8) * ay + 0.3 * p.half.x * ax;
            const Frame f = Frame::at({q, p.ground - 0.1}) * Frame::rotation({0, 0, 1}, p.yaw);
            for (const Part& part : make_hedge(rng, {p.half.x, 0.8, rng.uniform(0.9, 1.5)}))
                L.add(part.prim, f * part.frame, part.material, kTreeSigma);
        }
        if (rng.chance(0.4)) {
            const CarShape car = make_car(rng, car_paint(rng));
            const glm::dvec2 q = p.c - (p.half.y + 1.5) * ay - 0.6 * p.half.x * ax;
            L.add_parts(car.parts, Frame::at({q, p.ground}) * Frame::rotation({0, 0, 1}, p.yaw + 0.5 * kPi), 0.05, 0, 0);
        }
    }

    glm::dvec2 centre(0.0);
    for (const Plot& p : plots) centre += p.c / double(plots.size());
    double reach = 0.0;
    for (const Plot& p : plots) reach = std::max(reach, glm::length(p.c - centre) + glm::length(p.half));
    L.orbit.target = glm::dvec3(centre, terrain_at(centre) + 3.0);
    L.orbit.radius = std::max(40.0, 1.35 * reach);
    L.orbit.elevations = {30, 45, 60};
    L.orbit.radius_jitter = 0.05;
    L.orbit.target_jitter = 1.5;
    L.orbit.fov_x = 60;
    L.orbit.default_count = 72;
    L.sky.enabled = true;
    L.sky.radius = 1500.0;
    L.light.sun = glm::normalize(glm::dvec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(0.8, 1.5)));
    L.light.ambient = 0.5f;
    L.light.direct = 0.55f;
    L.light.shadow = 0.35f;
    L.detail_radius = 0.8 * L.orbit.radius;
    L.floater_region = Aabb{glm::dvec3(centre - 45.0, terrain_at(centre) + 2.0), glm::dvec3(centre + 45.0, terrain_at(centre) + 25.0)};
    L.floater_sigma = 0.3;
    return L;
}

}  // namespace pg::data::synth

// Campus suite (semantic): a few hundred metres of university campus on gentle terrain, in
// seven classes (suites.h): buildings of several forms (each its own instance, some adjoining),
// roads and parking lots, trees and lawns, parked cars, lamp posts, sports fields; sky and
// floaters are "other". The terrain is one shape whose class varies with position.
#include <algorithm>
#include <cmath>

#include "dataset/synth/buildings.h"
#include "dataset/synth/campus_ground.h"
#include "dataset/synth/suites.h"
#include "dataset/synth/texture.h"
#include "dataset/synth/vegetation.h"
#include "dataset/synth/vehicle.h"

namespace pg::data::synth {
namespace {

constexpr double kTerrain = 1100.0, kRoadHalf = 7.0;
constexpr int kGrid = 161;
constexpr double kBuildingSigma = 0.6, kGroundSigma = 2.4, kTreeSigma = 0.7, kCarSigma = 0.4;

Material mat(Albedo a, float gloss = 0.02f) {
    Material m;
    m.albedo = std::move(a);
    m.gloss = gloss;
    m.colour_noise = 0.05f;
    return m;
}

double terrain_height(const glm::dvec2& p, uint64_t seed) {
    return 10.0 * (fbm(glm::dvec3(p / 500.0, 0.5), 3, seed) - 0.5) + 0.8 * (fbm(glm::dvec3(p / 40.0, 1.5), 2, seed + 3) - 0.5);
}

FacadeStyle campus_facade(Rng& rng) {
    FacadeStyle st;
    const int scheme = rng.below(4);
    const glm::vec3 walls[] = {{0.72f, 0.7f, 0.66f}, {0.82f, 0.76f, 0.64f}, {0.62f, 0.36f, 0.28f}, {0.55f, 0.6f, 0.65f}};
    st.wall = walls[scheme] * float(rng.uniform(0.9, 1.1));
    st.bricks = scheme == 2;
    st.ribbon = scheme == 3 || rng.chance(0.3);
    st.glass = glm::vec3(0.15f, 0.22f, 0.3f) * float(rng.uniform(0.8, 1.3));
    st.roof = glm::vec3(float(rng.uniform(0.35, 0.6)));
    st.storey = rng.uniform(3.6, 4.2);
    st.window_width = rng.uniform(1.6, 2.6);
    st.window_height = rng.uniform(1.6, 2.2);
    st.bay = rng.uniform(3.0, 4.5);
    st.door = true;
    st.seed = rng.next();
    return st;
}

}  // namespace

std::vector<ClassInfo> campus_classes() {
    return {{kCampusOther, "other"},     {kCampusBuilding, "building"},
            {kCampusRoad, "road"},       {kCampusVegetation, "vegetation"},
            {kCampusVehicle, "vehicle"}, {kCampusStreetFurniture, "street furniture"},
            {kCampusOtherGround, "other ground"}};
}

Layout build_campus(uint64_t seed) {
    Rng rng(seed);
    Layout L;
    L.default_sh_degree = 1;
    L.classes = campus_classes();
    const uint64_t ground_seed = rng.next();

    // A road grid over the central 420 m; lots between the roads get a use.
    std::vector<double> xs = {-210.0}, ys = {-210.0};
    for (double x = -210.0; x < 150.0;) xs.push_back(x += rng.uniform(95.0, 140.0));
    for (double y = -210.0; y < 150.0;) ys.push_back(y += rng.uniform(95.0, 140.0));
    xs.back() = std::max(xs.back(), 210.0);
    ys.back() = std::max(ys.back(), 210.0);
    auto plan = std::make_shared<CampusPlan>();
    plan->road_x = xs;
    plan->road_y = ys;
    plan->road_half = kRoadHalf;
    plan->terrain_half = 0.5 * kTerrain;
    std::vector<Lot>& lots = plan->lots;
    for (size_t i = 0; i + 1 < xs.size(); ++i)
        for (size_t j = 0; j + 1 < ys.size(); ++j) {
            Lot lot{{xs[i] + kRoadHalf + 4.0, ys[j] + kRoadHalf + 4.0}, {xs[i + 1] - kRoadHalf - 4.0, ys[j + 1] - kRoadHalf - 4.0},
                    LotUse::Buildings};
            const double r = rng.uniform();
            lot.use = r < 0.7 ? LotUse::Buildings : (r < 0.8 ? LotUse::Sports : (r < 0.9 ? LotUse::Parking : LotUse::Park));
            lots.push_back(lot);
        }
    // Every scene holds every class: a use no lot drew takes a lot of buildings.
    for (LotUse use : {LotUse::Sports, LotUse::Parking, LotUse::Park}) {
        if (std::any_of(lots.begin(), lots.end(), [&](const Lot& l) { return l.use == use; })) continue;
        std::vector<size_t> free;
        for (size_t k = 0; k < lots.size(); ++k)
            if (lots[k].use == LotUse::Buildings) free.push_back(k);
        if (free.size() > 1) lots[free[size_t(rng.below(int(free.size())))]].use = use;
    }
    auto ground_at = [&](const glm::dvec2& p) { return terrain_height(p, ground_seed); };

    // Buildings: rows of one to three per lot (two rows in deep lots), sometimes joined.
    struct Footprint {
        glm::dvec2 c, half;
        double base;
    };
    std::vector<Footprint> footprints;
    int building = 0;
    for (const Lot& lot : lots) {
        if (lot.use != LotUse::Buildings) continue;
        const glm::dvec2 size = lot.hi - lot.lo;
        const int rows = size.y > 80.0 ? 2 : 1;
        for (int row = 0; row < rows; ++row) {
            const double y0 = lot.lo.y + row * size.y / rows, depth_room = size.y / rows;
            const int n = rng.between(1, 3);
            const bool joined = n > 1 && rng.chance(0.5);
            double x = lot.lo.x + rng.uniform(0.0, 8.0);
            for (int k = 0; k < n; ++k) {
                CampusBuildingSpec b;
                b.kind = BlockKind(rng.below(5));
                if (rows == 2 && b.kind == BlockKind::Courtyard) b.kind = BlockKind::Slab;
                b.length = std::min(lot.hi.x - x, rng.uniform(0.3, 0.7) * size.x);
                if (b.length < 18.0) break;
                b.depth = std::min(0.85 * depth_room, b.kind == BlockKind::Courtyard ? rng.uniform(45.0, 75.0) : rng.uniform(16.0, 38.0));
                b.height = b.kind == BlockKind::Tower ? rng.uniform(40.0, 75.0) : rng.uniform(10.0, 28.0);
                b.dome = b.kind == BlockKind::Hall && rng.chance(0.5);
                b.facade = campus_facade(rng);
                b.sink = 4.0;
                const glm::dvec2 c(x + 0.5 * b.length, y0 + rng.uniform(0.5 * b.depth, depth_room - 0.5 * b.depth));
                const double base = ground_at(c);
                const int id = L.add_instance(kCampusBuilding, "building_" + std::to_string(++building));
                const std::vector<Part> parts = make_campus_building(rng, b);
                L.add_parts(parts, Frame::at({c, base}), kBuildingSigma, id, kCampusBuilding);
                for (const Part& p : parts) {  // the blocks standing on the ground (not roofs, plant rooms)
                    const Aabb box = transform_box(p.frame, p.prim->bounds());
                    if (box.lo.z < 0.0)
                        plan->built.push_back({c + 0.5 * glm::dvec2(box.lo + box.hi), 0.5 * glm::dvec2(box.hi - box.lo)});
                }
                footprints.push_back({c, 0.5 * glm::dvec2(b.length, b.depth), base});
                x += b.length + (joined ? 0.0 : rng.uniform(10.0, 25.0));
            }
        }
    }

    // Terrain, levelled under the buildings; roads, lawns, fields and parking painted on.
    std::vector<double> heights(size_t(kGrid) * kGrid);
    const double cell = kTerrain / (kGrid - 1);
    auto levelled = [&](const glm::dvec2& q) {
        double h = ground_at(q);
        for (const Footprint& f : footprints) {
            const glm::dvec2 d = glm::max(glm::abs(q - f.c) - f.half, glm::dvec2(0.0));
            const double w = std::clamp(1.0 - (glm::length(d) - 4.0) / 15.0, 0.0, 1.0);
            h += (f.base - h) * w * w * (3.0 - 2.0 * w);
        }
        return h;
    };
    for (int j = 0; j < kGrid; ++j)
        for (int i = 0; i < kGrid; ++i)
            heights[size_t(j) * kGrid + size_t(i)] = levelled({-0.5 * kTerrain + i * cell, -0.5 * kTerrain + j * cell});
    Shape& terrain = L.add(make_heightfield(kGrid, kGrid, kTerrain, kTerrain, heights, -40.0), Frame{},
                           ground_material(plan, ground_seed), kGroundSigma, 0, kCampusOtherGround);
    terrain.class_at = ground_class(plan);

    // Trees along roads and in parks, cars in the parking lots, lamp posts.
    auto clear_of_buildings = [&](const glm::dvec2& q, double margin) {
        for (const Footprint& f : footprints)
            if (std::abs(q.x - f.c.x) < f.half.x + margin && std::abs(q.y - f.c.y) < f.half.y + margin) return false;
        return true;
    };
    auto add_tree = [&](const glm::dvec2& q) {
        const Frame f = Frame::at({q, levelled(q) - 0.3}) * Frame::rotation({0, 0, 1}, rng.uniform(0, 6.3));
        for (const Part& p : make_tree(rng, rng.uniform(8.0, 16.0), rng.chance(0.2)))
            L.add(p.prim, f * p.frame, p.material, kTreeSigma * p.sigma_scale, 0, kCampusVegetation);
    };
    for (double x : xs)
        for (double y = -200.0; y < 200.0; y += rng.uniform(14.0, 24.0)) {
            const glm::dvec2 q(x + rng.sign() * (kRoadHalf + 3.0), y);
            if (clear_of_buildings(q, 6.0) && rng.chance(0.7)) add_tree(q);
        }
    for (const Lot& lot : lots) {
        if (lot.use == LotUse::Park || lot.use == LotUse::Buildings) {
            const int n = lot.use == LotUse::Park ? rng.between(15, 30) : rng.between(2, 8);
            for (int k = 0; k < n; ++k) {
                const glm::dvec2 q(rng.uniform(lot.lo.x, lot.hi.x), rng.uniform(lot.lo.y, lot.hi.y));
                if (clear_of_buildings(q, 6.0)) add_tree(q);
            }
        }
        if (lot.use == LotUse::Parking) {
            const glm::dvec2 c = 0.5 * (lot.lo + lot.hi), h = 0.5 * (lot.hi - lot.lo);
            for (double row = -0.5; row <= 0.5; row += 0.5)
                for (double x = c.x - 0.8 * h.x; x < c.x + 0.8 * h.x; x += 2.6) {
                    if (!rng.chance(0.55)) continue;
                    CarShape car = make_car(rng, car_paint(rng));
                    for (Part& p : car.parts) p.material.keep_thin = true;  // about a pixel wide in the views
                    const glm::dvec2 q(x + 1.3, c.y + row * h.y);
                    L.add_parts(car.parts, Frame::at({q, levelled(q)}) * Frame::rotation({0, 0, 1}, 0.5 * kPi + (rng.chance(0.5) ? kPi : 0.0)),
                                kCarSigma, 0, kCampusVehicle);
                }
        }
    }
    Material steel = mat(plain(glm::vec3(0.3f), 0.05f, 1.0), 0.1f);
    steel.aligned = 1.0f;
    steel.keep_thin = true;
    for (double y : ys)
        for (double x = -200.0; x < 200.0; x += 30.0) {
            const glm::dvec2 q(x, y + kRoadHalf + 1.0);
            if (clear_of_buildings(q, 2.0)) L.add(make_capsule(0.12, 8.0), Frame::at({q, levelled(q)}), steel, 0.25, 0, kCampusStreetFurniture);
        }

    L.orbit.target = glm::dvec3(0.0, 0.0, ground_at({0.0, 0.0}) + 10.0);
    L.orbit.radius = rng.uniform(370.0, 420.0);
    L.orbit.elevations = {35, 50, 65};
    L.orbit.radius_jitter = 0.04;
    L.orbit.target_jitter = 10.0;
    L.orbit.fov_x = 60;
    L.orbit.default_count = 48;
    L.sky.enabled = true;
    L.sky.radius = 5000.0;
    L.light.sun = glm::normalize(glm::dvec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(0.9, 1.6)));
    L.light.ambient = 0.5f;
    L.light.direct = 0.55f;
    L.light.shadow = 0.35f;
    L.detail_radius = 260.0;
    L.floater_region = Aabb{glm::dvec3(-250, -250, 5), glm::dvec3(250, 250, 90)};
    L.floater_sigma = 1.5;
    return L;
}

}  // namespace pg::data::synth

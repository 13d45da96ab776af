#include "dataset/synth/campus_ground.h"

#include <cmath>

#include "dataset/synth/suites.h"
#include "dataset/synth/texture.h"

namespace pg::data::synth {

namespace {

// Lane paint: dashes 4 m long every 8 m along a road's centre line.
bool centre_dash(double across, double along) { return std::abs(across) < 0.15 && std::fmod(along + 1e4, 8.0) < 4.0; }

// The running track's elliptical distance in lot coordinates q (-1..1): the ring is 0.82..1.
double track_distance(const glm::dvec2& q) { return std::hypot(std::max(0.0, std::abs(q.x) - 0.35) / 0.55, q.y / 0.8); }

}  // namespace

Cover CampusPlan::cover(const glm::dvec2& p) const {
    for (double x : road_x)
        if (std::abs(p.x - x) < road_half) return centre_dash(p.x - x, p.y) ? Cover::RoadLine : Cover::Road;
    for (double y : road_y)
        if (std::abs(p.y - y) < road_half) return centre_dash(p.y - y, p.x) ? Cover::RoadLine : Cover::Road;
    for (const Lot& lot : lots) {
        if (p.x < lot.lo.x || p.y < lot.lo.y || p.x > lot.hi.x || p.y > lot.hi.y) continue;
        const glm::dvec2 q = (p - 0.5 * (lot.lo + lot.hi)) / (0.5 * (lot.hi - lot.lo));  // -1..1 within the lot
        if (lot.use == LotUse::Sports) {
            const double track = track_distance(q);
            if (track > 0.82 && track < 1.0) return Cover::Track;
            if (track <= 0.82) return std::abs(q.x) < 0.01 || std::abs(track - 0.8) < 0.01 ? Cover::FieldLine : Cover::Pitch;
        }
        if (lot.use == LotUse::Parking && std::abs(q.x) < 0.85 && std::abs(q.y) < 0.85) {
            const bool line = std::fmod(p.x + 1e4, 2.6) < 0.12 && std::abs(std::fmod(q.y + 10.0, 0.5) - 0.25) > 0.04;
            return line ? Cover::ParkingLine : Cover::Parking;
        }
        break;  // lots are disjoint: the rest of this one is lawn
    }
    return Cover::Lawn;
}

double CampusPlan::edge(const glm::dvec2& p) const {
    double d = std::max(0.0, terrain_half - std::max(std::abs(p.x), std::abs(p.y)));
    for (double x : road_x) d = std::min(d, std::abs(std::abs(p.x - x) - road_half));
    for (double y : road_y) d = std::min(d, std::abs(std::abs(p.y - y) - road_half));
    for (const Lot& lot : lots) {
        const glm::dvec2 c = 0.5 * (lot.lo + lot.hi), h = 0.5 * (lot.hi - lot.lo), a = glm::abs(p - c);
        // The track's outer edge: its distance function changes by at most 1 / (smaller semi-axis) per metre.
        if (lot.use == LotUse::Sports)
            d = std::min(d, std::abs(track_distance((p - c) / h) - 1.0) * std::min(0.55 * h.x, 0.8 * h.y));
        if (lot.use == LotUse::Parking) {  // the tarmac rectangle, exactly
            const glm::dvec2 b = 0.85 * h, out = glm::max(a - b, glm::dvec2(0.0));
            d = std::min(d, out.x > 0.0 || out.y > 0.0 ? glm::length(out) : std::min(b.x - a.x, b.y - a.y));
        }
    }
    for (const Rect& f : built) d = std::min(d, glm::length(glm::max(glm::abs(p - f.c) - f.half, glm::dvec2(0.0))));
    return d;
}

int cover_class(Cover c) {
    switch (c) {
        case Cover::Road:
        case Cover::RoadLine:
        case Cover::Parking:
        case Cover::ParkingLine: return kCampusRoad;
        case Cover::Track:
        case Cover::Pitch:
        case Cover::FieldLine: return kCampusOtherGround;
        case Cover::Lawn: return kCampusVegetation;
    }
    return kCampusOther;
}

Material ground_material(std::shared_ptr<const CampusPlan> plan, uint64_t seed) {
    const Albedo lawn = grass(glm::vec3(0.3f, 0.45f, 0.17f), seed, 15.0);
    const Albedo tarmac = asphalt(glm::vec3(0.3f), seed + 1);
    Material m;
    m.colour_noise = 0.05f;
    m.sink = false;
    m.albedo = [=](const glm::dvec3& p, const glm::dvec3& n) {
        switch (plan->cover(glm::dvec2(p))) {
            case Cover::Road:
            case Cover::Parking: return tarmac(p, n);
            case Cover::RoadLine:
            case Cover::ParkingLine: return glm::vec3(0.9f);
            case Cover::FieldLine: return glm::vec3(0.95f);
            case Cover::Track: return glm::vec3(0.62f, 0.25f, 0.2f);
            case Cover::Pitch: return glm::vec3(0.22f, 0.5f, 0.2f) * (std::fmod(p.x + 1e4, 10.0) < 5.0 ? 1.0f : 0.9f);
            case Cover::Lawn: break;
        }
        return lawn(p, n);
    };
    m.edge = [plan](const glm::dvec3& p) { return plan->edge(glm::dvec2(p)); };
    return m;
}

ClassAt ground_class(std::shared_ptr<const CampusPlan> plan) {
    return [plan = std::move(plan)](const glm::dvec3& p) { return cover_class(plan->cover(glm::dvec2(p))); };
}

}  // namespace pg::data::synth

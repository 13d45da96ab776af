#pragma once
// The campus plan on the ground: a road grid, the lots between its roads, and what covers the
// terrain at a point. The terrain's colour and its class both come from CampusPlan::cover, so
// the Gaussians' labels and the ray-cast masks follow the painted roads, lawns and fields.
#include <cstdint>
#include <memory>
#include <vector>

#include "dataset/synth/shape.h"

namespace pg::data::synth {

enum class LotUse { Buildings, Sports, Parking, Park };

struct Lot {
    glm::dvec2 lo, hi;
    LotUse use = LotUse::Buildings;
};

struct Rect {
    glm::dvec2 c, half;
};

enum class Cover { Lawn, Road, RoadLine, Track, Pitch, FieldLine, Parking, ParkingLine };

struct CampusPlan {
    std::vector<double> road_x, road_y;  // centre lines of the roads along y and along x
    double road_half = 7.0;
    std::vector<Lot> lots;               // disjoint, clear of the roads
    std::vector<Rect> built;             // ground under the buildings' walls
    double terrain_half = kInf;          // the terrain's half extent in x and y

    Cover cover(const glm::dvec2& p) const;  // canonical x-y
    // Distance to the nearest edge in the images of the ground: between covers of different
    // classes, around the buildings' walls, at the terrain's border (a lower bound near lot
    // corners and the track's bends), for sizing and placing the Gaussians there.
    double edge(const glm::dvec2& p) const;
};

int cover_class(Cover c);  // a CampusClass

// The terrain heightfield's material and class (its local coordinates are canonical).
Material ground_material(std::shared_ptr<const CampusPlan> plan, uint64_t seed);
ClassAt ground_class(std::shared_ptr<const CampusPlan> plan);

}  // namespace pg::data::synth

#pragma once
// Buildings for the residence and campus suites, in their own coordinates: footprint
// centred on the origin, ground at z = 0, front facing -y. Walls reach `sink` below the
// ground so they meet uneven terrain without a gap.
#include <vector>

#include "dataset/synth/layout.h"
#include "dataset/synth/texture.h"

namespace pg::data::synth {

enum class RoofKind { Gable, Hip, Flat };

struct HouseSpec {
    double width = 9, depth = 8;       // x, y
    int storeys = 2;
    double storey = 2.8;
    RoofKind roof = RoofKind::Gable;
    double pitch = 0.7;                // roof rise per run
    glm::vec3 wall{0.85f, 0.8f, 0.72f}, roof_colour{0.3f, 0.28f, 0.27f};
    bool bricks = false;
    bool chimney = true;
    int garage = 0;                    // -1: on the -x side, +1: on the +x side, 0: none
    double sink = 1.5;
    uint64_t seed = 1;
};
std::vector<Part> make_house(const HouseSpec& spec);
// Width along x including the garage.
double house_span(const HouseSpec& spec);
double house_height(const HouseSpec& spec);

enum class BlockKind { Slab, LShape, Courtyard, Tower, Hall };

struct CampusBuildingSpec {
    BlockKind kind = BlockKind::Slab;
    double length = 60, depth = 18, height = 20;  // overall footprint x, y and main height
    FacadeStyle facade;
    bool dome = false;                            // halls: a dome instead of a pitched roof
    double sink = 3.0;
};
std::vector<Part> make_campus_building(Rng& rng, const CampusBuildingSpec& spec);

}  // namespace pg::data::synth

#pragma once
// The four suites' scene builders: each makes a Layout in canonical coordinates (z up).
#include <cstdint>

#include "dataset/synth/layout.h"

namespace pg::data::synth {

Layout build_desk(uint64_t seed);       // metres: 7-10 objects on a 1.5 m table in a room
Layout build_vehicles(uint64_t seed);   // metres: 3-4 cars parked along a kerb
Layout build_residence(uint64_t seed);  // metres: 7-10 houses on rolling terrain, with trees
Layout build_campus(uint64_t seed);     // metres: a few hundred metres of campus, seven classes

std::vector<ClassInfo> desk_classes();
std::vector<ClassInfo> vehicles_classes();
std::vector<ClassInfo> residence_classes();
std::vector<ClassInfo> campus_classes();

// The campus suite's class ids (campus_classes() names them; models are trained on them).
enum CampusClass : int {
    kCampusOther = 0,            // sky, floaters, anything not below
    kCampusBuilding = 1,
    kCampusRoad = 2,             // road and parking tarmac with their markings
    kCampusVegetation = 3,       // trees, lawns and park grass
    kCampusVehicle = 4,          // parked cars
    kCampusStreetFurniture = 5,  // lamp posts
    kCampusOtherGround = 6,      // sports fields (track and pitch), other terrain
};

}  // namespace pg::data::synth

#pragma once
// Cars built from a rounded lower body, a tapered glass cabin, wheels, mirrors and an
// antenna: compound objects with thin parts.
#include <vector>

#include "dataset/synth/layout.h"

namespace pg::data::synth {

struct CarShape {
    std::vector<Part> parts;  // x forward, y left, z up; wheels on z = 0
    double length = 4.4, width = 1.8, height = 1.45;
};

// A hatchback, sedan or SUV with the given paint colour.
CarShape make_car(Rng& rng, glm::vec3 paint);

// Paint colours weighted like a real street (greys, white, black, a few colours).
glm::vec3 car_paint(Rng& rng);

}  // namespace pg::data::synth

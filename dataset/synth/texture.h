#pragma once
// Procedural albedo: lattice noise and the patterns the scenes paint with (wood grain,
// stripes, paper, facades with windows, roof tiles, asphalt, grass). Every pattern is a
// pure function of the local point, so a shape's texture moves with it.
#include <cstdint>

#include "dataset/report/palette.h"
#include "dataset/synth/shape.h"

namespace pg::data::synth {

float value_noise(const glm::dvec3& p, uint64_t seed);          // smooth, in [0, 1]
float fbm(const glm::dvec3& p, int octaves, uint64_t seed);     // sum of octaves, in [0, 1]
using report::hsv;                                              // h in turns (dataset/report/palette.h)

// A flat colour mottled by low-frequency noise of the given feature size.
Albedo plain(glm::vec3 colour, float mottle = 0.06f, double feature = 0.05, uint64_t seed = 1);
// Wood: rings along local x, light and dark tones; `period` is the grain spacing.
Albedo wood(glm::vec3 light, glm::vec3 dark, double period, uint64_t seed);
// Bands perpendicular to `axis` (a label around a can, a striped ball, lane paint).
Albedo stripes(glm::vec3 a, glm::vec3 b, double period, const glm::dvec3& axis, float duty = 0.5f);
// Checkerboard in the local x-y-z lattice.
Albedo checker(glm::vec3 a, glm::vec3 b, double cell);
// Printed paper: text lines along local x inside |x| < text_half.x, |y| < text_half.y.
Albedo paper(glm::vec3 colour, glm::dvec2 text_half, double line_pitch, uint64_t seed);

// Building walls: vertical faces get storeys of windows, other faces the roof colour.
struct FacadeStyle {
    glm::vec3 wall{0.8f, 0.76f, 0.7f};
    glm::vec3 trim{0.95f, 0.95f, 0.93f};
    glm::vec3 glass{0.18f, 0.24f, 0.3f};
    glm::vec3 roof{0.35f, 0.33f, 0.32f};
    double storey = 3.0;          // storey height
    double window_width = 1.2, window_height = 1.4, bay = 3.0;  // bay: window spacing
    double ground = 0.0;          // local z of the ground
    bool door = true;             // a door on the face whose normal is most -y
    bool bricks = false;
    bool ribbon = false;          // continuous window bands (offices)
    uint64_t seed = 1;
};
Albedo facade(const FacadeStyle& style);
// Roof tiles: rows along local x with per-tile shade noise.
Albedo roof_tiles(glm::vec3 colour, double row, uint64_t seed);
// Ground covers, by world-size features.
Albedo asphalt(glm::vec3 colour, uint64_t seed);
Albedo grass(glm::vec3 colour, uint64_t seed, double feature = 2.0);

}  // namespace pg::data::synth

#pragma once
// Colours for pictures of labels: HSV to RGB and the deterministic colour of a mask id, shared
// by the synthetic suites' contact sheets and the engine's mask overlays. Pure host code.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "dataset/formats/image_io.h"

namespace pg::data::report {

glm::vec3 hsv(float h, float s, float v);  // h in turns; s, v in [0, 1]

// Deterministic colour of a mask id: black for 0, well separated hues otherwise.
glm::u8vec3 mask_colour(uint16_t id);
// The colour of a semantic class id (rgb in [0, 1]): a fixed palette of well separated colours
// for the first classes (1 red, 2 purple, 3 green, 4 blue, 5 yellow, 6 orange), mask_colour beyond.
glm::vec3 class_colour(int id);
// An id mask (row-major, width*height) as an 8-bit RGB image.
Image8 colourise_mask(const std::vector<uint16_t>& mask, int width, int height);

}  // namespace pg::data::report

#pragma once
// A legend box (colour swatch and name per entry) drawn into a picture's corner: class
// overlays carry their key with them.
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "dataset/formats/image_io.h"

namespace pg::data::report {

struct LegendEntry {
    std::string name;
    glm::vec3 colour{0.0f};  // rgb in [0, 1]
};

// Into the top-left corner of an RGB8 image, clipped to the image.
void draw_legend(Image8& img, const std::vector<LegendEntry>& entries);

}  // namespace pg::data::report

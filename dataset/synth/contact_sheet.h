#pragma once
// A contact sheet of a synthetic scene: views and their colourised ground-truth masks tiled
// into one image, for a quick look at what a suite contains. Pure image code; the CLI
// renders the RGB views and writes the sheet; masks are coloured by dataset/report/palette.h.
#include <cstdint>
#include <filesystem>
#include <vector>

#include <glm/glm.hpp>

#include "dataset/formats/image_io.h"

namespace pg::data::synth {

// Tiles in reading order, `columns` per row, `gap` pixels of dark grey between and around
// them. Pairs (rgb[i], mask[i]) sit side by side, so a row holds columns/2 views when
// both lists are given; either list may be empty. Tiles of other sizes are placed at the
// top-left of a cell sized for the largest. Images must be RGB (3 channels).
Image8 make_contact_sheet(const std::vector<Image8>& rgb, const std::vector<Image8>& masks, int columns, int gap = 4);

void write_contact_sheet(const std::filesystem::path& path, const Image8& sheet);

}  // namespace pg::data::synth

#pragma once
// Binary masks shared by the 2D (pixels, row-major) and 3D (one entry per Gaussian) click
// simulators: one byte per element, non-zero = inside. Bytes rather than std::vector<bool>
// so masks can be viewed as spans and filled from label arrays without bit twiddling.
#include <cstdint>
#include <span>
#include <vector>

namespace pg::data::clicks {

using Mask = std::vector<uint8_t>;

// Intersection over union; 1 when both masks are empty (nothing to find, nothing found).
// Throws InputError if the sizes differ.
double iou(std::span<const uint8_t> gt, std::span<const uint8_t> prediction);

// Mask of the elements whose label equals `id` (an instance or class id).
Mask mask_of(std::span<const int32_t> labels, int32_t id);
Mask mask_of(std::span<const uint16_t> labels, uint16_t id);

size_t count(std::span<const uint8_t> mask);

}  // namespace pg::data::clicks

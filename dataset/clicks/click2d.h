#pragma once
// Simulated user clicks on the pixels of one view, by the same protocol as click3d.h:
// each click at the most interior pixel of the largest error region, positive in a false
// negative region, negative in a false positive one; the first click (empty prediction)
// at the most interior pixel of the object's largest visible part.
//
// - Interior: exact Euclidean distance to the nearest pixel outside the region, pixels
//   beyond the image border counting as outside (RITM / InterObject3D padding), so a
//   region touching the border is pushed away from it.
// - Regions: 8-connected components, false negatives and false positives separately.
// - Largest: most pixels. Ties, here and for the most interior pixel, go to the lowest
//   row-major index (v * width + u).
#include <cstdint>
#include <optional>
#include <span>

namespace pg::data::clicks {

// A pixel; its centre, where a click is lifted to a ray, is (u + 0.5, v + 0.5).
struct Click2D {
    int u = 0, v = 0;      // column, row (top row 0)
    bool positive = true;
};

// Masks are width * height bytes, row-major, non-zero = inside. nullopt when the
// prediction equals the ground truth. Throws InputError on bad sizes.
std::optional<Click2D> next_click_2d(int width, int height, std::span<const uint8_t> gt,
                                     std::span<const uint8_t> prediction);
// next_click_2d with an empty prediction; nullopt for an empty ground truth.
std::optional<Click2D> first_click_2d(int width, int height, std::span<const uint8_t> gt);

}  // namespace pg::data::clicks

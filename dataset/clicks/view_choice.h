#pragma once
// Which view to click an object in, the way a user of the viewer would: the one where the
// object covers the most pixels.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace pg::data::clicks {

// Pixels labelled `id` in one 16-bit id mask.
size_t visible_area(std::span<const uint16_t> ids, uint16_t id);

// The index of the view whose id mask (e.g. SUITE_DIR/<scene>/masks/<camera>.png, in
// camera order) shows object `id` on the most pixels; ties -> the lowest index; nullopt
// if no view shows it. Masks may differ in size.
std::optional<size_t> choose_view_for_object(std::span<const std::vector<uint16_t>> views, uint16_t id);

}  // namespace pg::data::clicks

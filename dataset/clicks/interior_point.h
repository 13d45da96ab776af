#pragma once
// The most interior point of a set S of points in a cloud: the member whose distance to
// the nearest non-member (any cloud point outside S) is largest.
//
// Distances are capped at `cap` = max(half the largest side of S's bounding box,
// min_cap): no point can lie deeper than half the set's extent, so a larger distance only
// says the set stands apart from everything else (a floater, an object in free space),
// not how interior a point is. All members at the cap are tied; among them the one
// nearest to their centroid wins, which gives the centre of an isolated set rather than
// its side facing away from the rest. Remaining ties go to the lowest index.
//
// Exact, and fast on large sets: a dense grid over S's box grown by the cap (at most
// kMaxCells cells) marks the cells holding non-members; an exact distance transform over
// it bounds every member's distance to within one cell diagonal, and exact nearest-non-
// member queries (a k-d tree) run only on the members whose upper bound can still beat
// the best found.
#include <cstdint>
#include <span>

#include <glm/glm.hpp>

namespace pg::data::clicks {

// About 80 cells along the region: the transform takes a few milliseconds, and bounds one
// cell diagonal wide leave few members needing an exact query.
constexpr int kMaxCells = 1 << 19;

// `in_set` marks S (one byte per point), `members` lists its indices in ascending order
// (non-empty). `min_cell` keeps the grid no finer than useful (about the point spacing).
uint32_t most_interior_point(std::span<const glm::vec3> positions, std::span<const uint8_t> in_set,
                             std::span<const uint32_t> members, float min_cap, float min_cell);

}  // namespace pg::data::clicks

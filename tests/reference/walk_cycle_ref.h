#pragma once
// CPU reference of the random walker's multigrid V-cycle (random_walker.cpp with walk_restrict,
// walk_coarsest, walk_smooth), in double, on a hierarchy built by engine/segment/walk_hierarchy:
// z = B r with one Jacobi sweep before and after the coarse correction, scaled by `scale`.
#include <cstdint>
#include <vector>

#include "engine/segment/walk_hierarchy.h"

namespace pg::ref {

// r and the result: `width` columns per node of level 0, node-major.
std::vector<double> walk_cycle(const seg::WalkHierarchy& h, double scale, uint32_t width, const std::vector<double>& r);

}  // namespace pg::ref

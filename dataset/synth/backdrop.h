#pragma once
// Gaussians that are not on any shape, as trained captures have them: a far sky dome of
// large splats and low-opacity floaters in the air. Neither appears in the masks.
#include "dataset/synth/layout.h"

namespace pg::data::synth {

// A dome of splats facing `centre` at sky.radius, down to 15 degrees below the horizon.
SplatList sky_dome(const SkySpec& sky, const glm::dvec3& centre, const glm::dvec3& up, int sh_degree, uint64_t seed);

// `count` blobs in `region` (canonical coordinates, mapped by `world`), outside every shape.
SplatList floaters(const ShapeSet& shapes, const Aabb& region, const Frame& world, size_t count, double sigma,
                   int sh_degree, uint64_t seed);

}  // namespace pg::data::synth

#pragma once
// Cameras of a synthetic capture: 360-degree orbits at several elevations around the
// layout's target, a little hand-held jitter, never inside a shape.
#include <vector>

#include "dataset/camera.h"
#include "dataset/synth/layout.h"

namespace pg::data::synth {

// `count` cameras named view_000.. (ring by ring), world-to-camera OpenCV, looking at
// spec.target mapped by `world`, with world up = world.R * +z appearing up in the image.
std::vector<Camera> orbit_rig(const OrbitSpec& spec, const Frame& world, int count, int width, int height,
                              double fov_x, const ShapeSet& shapes, uint64_t seed);

}  // namespace pg::data::synth

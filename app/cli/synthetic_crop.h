#pragma once
// A synthetic click crop for benchmarks: n distinct voxels on the surfaces of a few boxes and
// spheres over a floor, with a positive click weight on the first shape and a negative one on
// the second as features (channels beyond two are 0).
#include <cstdint>

#include "nn/ptv3/model.h"

namespace pg::app {

nn::Ptv3Input synthetic_crop(int n, int channels, double grid, uint64_t seed);

}  // namespace pg::app

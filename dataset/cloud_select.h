#pragma once
// A sub-cloud of chosen Gaussians (one extracted object), keeping every property, its
// order and type, so the file opens in other 3DGS tools.
#include <cstdint>
#include <vector>

#include "dataset/gaussian_cloud.h"

namespace pg::data {

GaussianCloud select_gaussians(const GaussianCloud& cloud, const std::vector<uint32_t>& indices);

}  // namespace pg::data

#pragma once
// The host side of a streamed frame: which Gaussians preprocess could draw, front to back,
// so consecutive runs of them make the slabs.
#include <cstdint>
#include <utility>
#include <vector>

#include "dataset/camera.h"
#include "dataset/gaussian_cloud.h"
#include "engine/render/renderer.h"

namespace pg::render {

// (depth key, scene index) of every Gaussian that may reach a pixel, sorted by key then index:
// the order of the renderer's stable depth sort, whose key (the float view depth's bits) it is.
std::vector<std::pair<uint32_t, uint32_t>> slab_order(const data::GaussianCloud& cloud, const data::Camera& camera,
                                                      const RenderSettings& settings);

// Stable LSD radix sort on the first member (8 bits a pass).
void radix_sort_by_key(std::vector<std::pair<uint32_t, uint32_t>>& items);

}  // namespace pg::render

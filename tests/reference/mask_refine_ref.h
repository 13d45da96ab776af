#pragma once
// CPU reference of engine/segment/mask_refine: the same three stages, written plainly from
// their definitions (see engine/segment/mask_refine.h), for the tests. No Vulkan.
#include <cstdint>
#include <vector>

namespace pg::ref {

using LabelImage = std::vector<uint32_t>;  // row-major, width x height, 0 = background

// One closing radius: every 0-pixel in erode_r(dilate_r(mask_k)) of some instance k takes the
// smallest such k (outside the image: not-k for the dilation, k for the erosion).
LabelImage close_labels(const LabelImage& labels, int width, int height, int radius);
// 4-connected 0-components off the border whose outside 4-neighbours are all one instance.
LabelImage fill_label_holes(const LabelImage& labels, int width, int height);
// Per instance, only its largest 8-connected component (ties: lowest pixel index) stays.
LabelImage keep_largest_components(const LabelImage& labels, int width, int height);

// The stages in order, as MaskRefiner::refine runs them.
LabelImage refine_labels(const LabelImage& labels, int width, int height, const std::vector<int>& closing_radii,
                         bool fill_holes, bool largest_component);

}  // namespace pg::ref

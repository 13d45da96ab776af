#pragma once
// CPU reference of the GPU label rasterizer (engine/segment/label_raster.h): per-pixel label
// images from per-Gaussian labels, in float like the GPU and with the renderer's binning
// rule, but no tiling tricks: every pixel walks its tile's whole list, front to back.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "dataset/camera.h"
#include "dataset/gaussian_cloud.h"
#include "tests/reference/cpu_rasterizer.h"

namespace pg::ref {

enum class LabelMode {
    Paper,      // first labelled Gaussian of the tile list whose centre is within rho^2 <= 4 px^2
    Occlusion,  // label of largest blending weight (unlabelled counts as 0) where 1 - T >= 0.5
};

constexpr int kLabelTile = 16;              // the renderer's tile size
constexpr float kLabelRho2Max = 4.0f;       // Paper: squared centre distance, px^2
constexpr int kLabelSlots = 8;              // Occlusion: labels > 0 tracked per pixel
constexpr float kLabelMinCoverage = 0.5f;   // Occlusion: 1 - T below this gives 0

// A frame's Gaussians as the renderer bins them: projected (culled ones dropped), sorted
// front to back (ties by index), and listed per 16x16 tile where the ellipse of alpha >= 1/255
// (with the renderer's 1.0001 margin) reaches a pixel centre of the tile; tiles whose
// bounding rectangle holds at most two tiles take them all, as the renderer does.
struct TileBins {
    int width = 0, height = 0, tiles_x = 0, tiles_y = 0;
    std::vector<ProjectedGaussian> splats;         // depth order
    std::vector<std::vector<uint32_t>> tiles;      // per tile, row-major: indices into splats
};
TileBins bin_gaussians(const pg::data::GaussianCloud& cloud, const pg::data::Camera& camera,
                       const RefOptions& options = {});

struct LabelStats {
    size_t overflow_pixels = 0;  // Occlusion: pixels that saw more than kLabelSlots labels > 0
};

// Label image, row-major, top row first; labels[i] is Gaussian i's label (0: unlabelled;
// missing entries count as 0).
std::vector<uint32_t> label_reference(const pg::data::GaussianCloud& cloud, const pg::data::Camera& camera,
                                      const std::vector<uint32_t>& labels, LabelMode mode,
                                      const RefOptions& options = {}, LabelStats* stats = nullptr);

}  // namespace pg::ref

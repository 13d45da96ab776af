#pragma once
// Exact squared Euclidean distance transforms (Felzenszwalb & Huttenlocher, "Distance
// Transforms of Sampled Functions", 2012): one lower-envelope-of-parabolas pass per axis,
// linear time. Distances are in grid units between cell (pixel) centres.
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace pg::data::clicks {

constexpr double kFar = std::numeric_limits<double>::infinity();

// d[q] = min_p (q - p)^2 + f[p] over the n samples f (kFar allowed: not a site).
// All kFar in, all kFar out. `sites` and `bounds` are scratch of size n and n + 1.
void squared_edt_1d(const double* f, int n, double* d, int* sites, double* bounds);

// For each pixel of the w x h region mask (row-major, non-zero = inside): the squared
// distance to the nearest pixel outside the region, 0 for outside pixels. Pixels beyond
// the image border count as outside (the mask is padded with "not in region", as RITM and
// InterObject3D do), so a region pixel on the border is at distance 1.
std::vector<double> squared_distance_to_outside(int w, int h, std::span<const uint8_t> region);

// In place on a dense nx*ny*nz grid (x fastest): grid holds 0 at sites and kFar elsewhere,
// and becomes the squared distance from each cell centre to the nearest site centre.
void squared_edt_3d(std::vector<double>& grid, int nx, int ny, int nz);

}  // namespace pg::data::clicks

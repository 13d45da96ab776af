#pragma once
// The GPU half of engine/compress/kmeans: Lloyd steps from given centroids. A step is
//   compress/kmeans_assign_dD  per window of points and block of centroids: nearest so far
//   sort/radix_*               per window: its labels, stably, with the points' indices
//   compress/kmeans_bounds     per window: where each cluster's run of members starts and ends
//   compress/kmeans_piece_sums per window: Kahan sums of the runs, cut into bounded chunks
//   compress/kmeans_accumulate per window: the runs' sums and counts added to the running ones
//   compress/kmeans_update     the means (an empty cluster keeps its centroid)
// and the labels come from one more assignment after the last step. Windows keep every
// binding within the device's maxStorageBufferRange, so any number of points fits.
#include <cstddef>
#include <vector>

#include "engine/compress/kmeans.h"
#include "engine/vk/context.h"

namespace pg::compress {

// `iterations` Lloyd steps of the points (n * dims floats, dims 1..kMaxKmeansDims) from
// `centroids` (k * dims floats). `max_window` (a multiple of 64; 0: as the device allows) caps
// the points per window, so tests can run the windowed update on small inputs.
Clusters lloyd(vk::Context& ctx, const std::vector<float>& points, size_t dims, std::vector<float> centroids,
               int iterations, size_t max_window = 0);

}  // namespace pg::compress

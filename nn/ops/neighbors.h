#pragma once
// Submanifold neighbour maps (spconv SubMConv3d's kernel map) for the sparse convolutions.
#include "nn/tensor.h"

namespace pg::nn::ops {

// Kernel size k (3 or 5), grid [N,3] int32 >= 0 of DISTINCT voxels, batch [N] int32 >= 0:
// nbr [N, k^3] I32, entry t = (rx*k + ry)*k + rz holds the index of the point at
// grid + (rx - k/2, ry - k/2, rz - k/2) in the same batch, or -1 (cross-correlation order).
// Recorded only, no host wait. Should a voxel repeat, its lowest point index is the one found.
// The bit widths of max batch, x, y, z must add up to at most key_bits (64: PTv3 depth <= 16 per
// axis); a caller that knows a smaller bound passes it, for fewer radix passes. A bound that is
// too small is not detected (no host wait here) and loses neighbours.
Tensor neighbor_map(vk::CommandList& cmd, Pool& pool, const Tensor& grid, const Tensor& batch, int kernel,
                    int key_bits = 64);

}  // namespace pg::nn::ops

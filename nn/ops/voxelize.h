#pragma once
// Unique voxels of a batch of clouds (Pointcept's GridSample at test time): one voxel per
// distinct (batch, x, y, z), represented by its lowest-index point.
#include <cstdint>

#include "nn/tensor.h"

namespace pg::nn::ops {

// grid [N,3] int32 >= 0, batch [N] int32 >= 0 -> the distinct (batch, x, y, z), sorted by
// (batch, x, y, z): grid [V,3] I32, batch [V] I32, inverse [N] I32 (point -> voxel), first [V]
// I32 (voxel -> smallest point index in it; the representative), count V. Records into cmd,
// then waits on the host once (V is data-dependent). key_bits: a bound the caller knows on the
// bit widths of the largest batch, x, y and z added up (fewer radix passes); throws
// std::invalid_argument for negative entries or when the widths add up to more.
struct Voxels {
    Tensor grid, batch, inverse, first;
    int64_t count = 0;
};
Voxels voxelize(vk::CommandList& cmd, Pool& pool, const Tensor& grid, const Tensor& batch, int key_bits = 64);

namespace detail {
struct IndexState;
// Packed (batch, x, y, z) keys sorted ascending (U64 [N]) with their point indices (U32 [N],
// ascending among equal keys) and the info tensor holding the maxima that fixed the packing.
// Recorded only; the packing needs at most key_bits (voxelize checks, neighbor_map assumes).
struct SortedGrid {
    Tensor keys, points, info;
};
SortedGrid sort_grid(vk::CommandList& cmd, Pool& pool, IndexState& state, const Tensor& grid, const Tensor& batch,
                     int key_bits);
}  // namespace detail

}  // namespace pg::nn::ops

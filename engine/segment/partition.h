#pragma once
// Density-adaptive partitioning: an ROI with more than N_max Gaussians becomes disjoint
// batches of at most N_max, each a seeded random subset, so every batch spans the whole ROI
// at a lower density (the paper's B_k) rather than cutting the object into tiles.
#include <cstdint>
#include <vector>

namespace pg::seg {

constexpr uint32_t kMaxBatch = 8192;

// ceil(n / max_batch) batches whose sizes differ by at most one; each batch's indices are
// ascending. The same (indices, max_batch, seed) give the same batches.
std::vector<std::vector<uint32_t>> partition_roi(const std::vector<uint32_t>& roi, uint32_t max_batch, uint64_t seed);

}  // namespace pg::seg

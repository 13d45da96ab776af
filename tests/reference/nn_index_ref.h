#pragma once
// CPU references of the PTv3 structure ops (nn/ops serialize, voxelize, neighbors, pooling),
// written straight from the semantics in ../shared/reference/ptv3-semantics.md.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace pg::test::ref {

// A random batch of clouds: grid [n,3] in [0, extent) per axis, batch [n] in [0, clouds).
// distinct: no (batch, x, y, z) twice (n is capped at what the extent allows).
struct Cloud {
    std::vector<int32_t> grid, batch;
    size_t size() const { return batch.size(); }
};
Cloud random_cloud(size_t n, int clouds, int extent, uint64_t seed, bool distinct);
// Bit lengths of the largest batch, x, y and z added up: the packed key's exact width.
int grid_key_bits(const Cloud& c);

// Orders by index, as in the model config: 0 z, 1 z-trans, 2 hilbert, 3 hilbert-trans.
uint64_t z_order_code(uint32_t x, uint32_t y, uint32_t z, int depth);
uint64_t hilbert_code(uint32_t x, uint32_t y, uint32_t z, int depth);
// (batch << 3 depth) | curve(grid) for grid [n,3], batch [n].
std::vector<uint64_t> serialize_codes(const std::vector<int32_t>& grid, const std::vector<int32_t>& batch, int order,
                                      int depth);

struct Sorted {
    std::vector<int32_t> order, inverse;
};
// Stable argsort on the low key_bits bits.
Sorted argsort(const std::vector<uint64_t>& codes, int key_bits = 64);

struct Voxels {
    std::vector<int32_t> grid, batch, inverse, first;  // grid [V,3]
};
Voxels voxelize(const std::vector<int32_t>& grid, const std::vector<int32_t>& batch);

// nbr [n, k^3], entry (rx*k + ry)*k + rz.
std::vector<int32_t> neighbor_map(const std::vector<int32_t>& grid, const std::vector<int32_t>& batch, int kernel);

struct Clusters {
    std::vector<int32_t> cluster, members, ptr, head;
};
// Clusters of the unique values of code >> shift (torch.unique sorted, return_inverse).
Clusters pool_clusters(const std::vector<uint64_t>& code, int shift);
// y [M, channels] = max over each cluster's members of x [n, channels].
std::vector<float> segment_max(const std::vector<float>& x, int channels, const Clusters& c);

}  // namespace pg::test::ref

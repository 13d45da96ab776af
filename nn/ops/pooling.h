#pragma once
// Serialized pooling (PTv3's SerializedPooling): clusters of points whose codes agree above
// `shift` bits, the max over each cluster, and the next level's codes, grid and batch.
#include <cstdint>

#include "nn/tensor.h"

namespace pg::nn::ops {

// Serialized pooling clusters: key = code >> shift (shift = 3 for stride 2); the unique keys,
// ascending, are clusters 0..M-1. cluster [N] I32 (torch.unique(..., return_inverse), i.e.
// Pointcept's pooling_inverse); members [N] I32 = point indices grouped by cluster (ascending
// inside a cluster); ptr [M+1] I32 offsets into members; head [M] I32 = first member of each
// cluster. Records into cmd, then waits on the host once (for M).
struct Clusters {
    Tensor cluster, members, ptr, head;
    int64_t count = 0;
};
Clusters pool_clusters(vk::CommandList& cmd, Pool& pool, const Tensor& code, int shift);
// Same, sorting only the code's low `code_bits` bits (3*depth + bits of the batch count): fewer
// radix passes than the 64 bits above. Bits above code_bits must be zero.
Clusters pool_clusters(vk::CommandList& cmd, Pool& pool, const Tensor& code, int shift, int code_bits);

// y[m,:] = max over the members of cluster m of x[member,:] (f32 [N,C] -> [M,C]).
Tensor segment_max(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Clusters& clusters);
// Next level's codes: code[head] >> shift (U64 [N] -> [M]).
Tensor pool_codes(vk::CommandList& cmd, Pool& pool, const Tensor& code, const Clusters& clusters, int shift);
// Next level's grid: grid[head] >> shift_bits (I32 [N,3] -> [M,3]).
Tensor pool_grid(vk::CommandList& cmd, Pool& pool, const Tensor& grid, const Clusters& clusters, int shift_bits);
// Next level's batch: batch[head] (I32 [N] -> [M]).
Tensor gather_batch(vk::CommandList& cmd, Pool& pool, const Tensor& batch, const Clusters& clusters);

namespace detail {
struct IndexState;
// Marks where runs of equal keys start in sorted U64 keys [n] and scans the marks in place
// (exclusive), writing the run count to info[PG_INFO_COUNT]; run r of item j is then
// starts[j] - 1 + (j starts a run).
void number_runs(vk::CommandList& cmd, IndexState& state, const Tensor& keys, const Tensor& starts,
                 const Tensor& info, uint32_t n);
}  // namespace detail

}  // namespace pg::nn::ops

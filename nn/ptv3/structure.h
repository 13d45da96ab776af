#pragma once
// The part of a PTv3 forward that depends on the coordinates only: voxels, and per level the
// grid, serialization orders, neighbour maps, attention offsets and pooling clusters.
// Inference and training build it the same way, then run their feature passes over it.
#include <cstdint>
#include <string>
#include <vector>

#include "nn/ops/pooling.h"
#include "nn/ops/serialize.h"
#include "nn/ops/sparse_conv.h"
#include "nn/ops/voxelize.h"
#include "nn/ptv3/config.h"
#include "nn/tensor.h"

namespace pg::nn {

struct Ptv3Input;

// One resolution of the U-Net: its voxels, serialization and neighbourhoods.
struct Ptv3Level {
    int64_t n = 0;
    int depth = 0;
    Tensor grid, batch;
    std::vector<int32_t> batch_host;
    std::vector<Tensor> codes;        // per order kind (config.order index)
    std::vector<ops::Sorted> sorted;  // per order kind
    std::vector<int> rows;            // row j of the release's code tensor holds kind rows[j]
    Tensor nbr3;
    ops::Rulebook rules3;             // nbr3's, built once for all the level's convolutions
    Tensor offsets;                   // attention: cloud boundaries in serialized positions
    std::vector<int32_t> offsets_host;
    ops::Clusters clusters;           // from the finer level (levels > 0)

    // The serialized order block `index` of this level attends in.
    const Tensor& order_for_block(int index) const { return sorted[size_t(rows[size_t(index) % rows.size()])].order; }
};

struct Ptv3Structure {
    ops::Voxels vox;
    Tensor nbr5;  // the embedding's 5x5x5 map at level 0
    std::vector<Ptv3Level> levels;
    int clouds = 1;
};

// Records the structure passes into cmd; the host waits for the voxel count and once per
// pooling (cluster counts). Timings of the submitted passes are appended to `passes`.
// The input must have passed Ptv3::validate.
Ptv3Structure build_structure(vk::CommandList& cmd, Pool& pool, const Ptv3Config& config, const Ptv3Input& input,
                              std::vector<vk::PassTiming>& passes);

}  // namespace pg::nn

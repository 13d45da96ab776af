#pragma once
// PTv3 inference: Pointcept's PointTransformerV3 (as in the PointGauss release) recorded as
// GLSL compute passes. The host waits only where a size is data-dependent: once for the
// voxel count and once per pooling for the cluster count.
//
// Duplicate voxels: the release feeds every point and lets spconv race on shared voxels.
// Here each voxel is represented by its lowest-index point (Pointcept's test-time
// GridSample), the network runs on the voxels, and every point gets its voxel's logits.
#include <array>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "nn/ptv3/network.h"
#include "nn/ptv3/weights.h"
#include "nn/tensor.h"

namespace pg::nn {

struct Ptv3Input {
    std::vector<float> coord;  // [n, 3] metres
    std::vector<float> feat;   // [n, in_channels]
    // Cloud ends as Pointcept's `offset` (cumulative counts); empty = one cloud.
    std::vector<int64_t> offsets;
    // Serialization order permutation per level (input + one per pooling), as the release's
    // shuffle draws them: level l's code rows are level l-1's rows permuted by perms[l].
    // Empty = fixed orders (block i uses order i % 4).
    std::vector<std::vector<int>> perms;
    // Count sparse-conv pairs for `Ptv3Output::flops` (downloads the neighbour maps; for bench).
    bool count_conv_pairs = false;
    size_t size() const { return coord.size() / 3; }
};

struct Ptv3Output {
    std::vector<float> logits;         // [n, classes], row i for input point i
    int64_t voxels = 0;                // distinct voxels the network ran on
    std::vector<int64_t> level_points; // points per encoder level
    std::vector<vk::PassTiming> passes; // GPU time of every recorded pass (names are op families)
    // Multiply-adds x 2 per op family: linear, attention (QK and PV), sparse_conv (over
    // existing neighbour pairs; only with count_conv_pairs).
    std::map<std::string, double> flops;
};

// Called with intermediate tensors named like the release's trace ("embedding/feat",
// "enc.enc2.block0/feat", "dec.dec0.up/feat", ...); rows are in voxel order at level 0
// (see Ptv3::voxel_points) and in cluster order below.
using Ptv3Trace = std::function<void(const std::string& name, const Tensor& t)>;

class Ptv3 {
public:
    Ptv3(Pool& pool, Ptv3Weights weights);
    const Ptv3Config& config() const { return weights_.config(); }
    const Ptv3Weights& weights() const { return weights_; }

    Ptv3Output forward(const Ptv3Input& input, const Ptv3Trace& trace = {});
    // After a forward: the input point that represents each level-0 voxel.
    // (Read from the device on demand: only tracing needs it.)
    std::vector<int32_t> voxel_points() const;

    // Throws std::invalid_argument naming what is wrong with an input for this config.
    static void validate(const Ptv3Config& config, const Ptv3Input& input);
    // The release's grid: trunc((coord - min over the batch) / grid_size), in float32.
    static std::vector<int32_t> grid_coords(const std::vector<float>& coord, double grid_size);

private:
    Pool& pool_;
    Ptv3Weights weights_;
    Ptv3Network network_;
    Tensor voxel_points_;  // I32 [voxels]
};

}  // namespace pg::nn

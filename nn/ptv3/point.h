#pragma once
// What flows between PTv3's modules, as Pointcept's Point: the structure built from the
// coordinates, the level the features live at, and the features. The backward walk sends the
// same struct the other way, each field then holding the loss gradient of what it held forward.
#include <vector>

#include "nn/ptv3/structure.h"
#include "nn/tensor.h"

namespace pg::nn {

struct Ptv3Point {
    const Ptv3Structure* structure = nullptr;
    int level = 0;
    Tensor feat;  // [level's voxels, channels]; before the embedding, [points, in_channels]
    // What the next block's CPE convolves when it is not `feat`. Pointcept's unpooling updates
    // feat but not sparse_conv_feat, so the first block after it convolves the skip projection
    // alone; the trained weights expect that. Blocks leave it undefined (= feat).
    Tensor conv_feat;
    // Pointcept's pooling_parent: the features of each finer level, pushed by a pooling and
    // taken back by the unpooling to that level.
    std::vector<Tensor> parents;

    const Ptv3Level& at() const { return structure->levels[size_t(level)]; }
};

}  // namespace pg::nn

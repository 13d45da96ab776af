#pragma once
// Training inputs: clouds appended into one multi-cloud Ptv3Input (offsets at their ends)
// with a label per point, and dataset/train samples as network inputs.
#include <cstdint>
#include <vector>

#include "dataset/train/sample_drawer.h"
#include "nn/ptv3/model.h"

namespace pg::nn::train {

struct Batch {
    Ptv3Input input;
    std::vector<int32_t> labels;  // per point

    // Appends one cloud: coord [n, 3], feat [n, in_channels], labels [n].
    void add(const std::vector<float>& coord, const std::vector<float>& feat, const std::vector<int32_t>& labels);
    void add(const data::train::Sample& sample) { add(sample.coord, sample.feat, sample.labels); }
};

// One sample (interactive or semantic: anything with coord and feat) as a one-cloud input (no offsets).
template <class Sample> Ptv3Input sample_input(const Sample& sample) {
    Ptv3Input in;
    in.coord = sample.coord;
    in.feat = sample.feat;
    return in;
}

}  // namespace pg::nn::train

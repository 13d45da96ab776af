#include "nn/train/batch.h"

namespace pg::nn::train {

void Batch::add(const std::vector<float>& coord, const std::vector<float>& feat, const std::vector<int32_t>& l) {
    input.coord.insert(input.coord.end(), coord.begin(), coord.end());
    input.feat.insert(input.feat.end(), feat.begin(), feat.end());
    labels.insert(labels.end(), l.begin(), l.end());
    input.offsets.push_back(int64_t(input.size()));
}

}  // namespace pg::nn::train

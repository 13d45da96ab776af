#include "nn/train/validation.h"

#include <algorithm>

#include "dataset/clicks/mask.h"
#include "nn/train/batch.h"

namespace pg::nn::train {

std::vector<uint8_t> predict_mask(Ptv3& model, const data::train::Sample& s) {
    const auto out = model.forward(sample_input(s));
    std::vector<uint8_t> mask(s.size());
    for (size_t i = 0; i < s.size(); ++i) mask[i] = out.logits[2 * i + 1] > out.logits[2 * i];
    return mask;
}

Validation validate(Pool& pool, const Ptv3Weights& weights, const data::train::SampleDrawer& drawer,
                    std::vector<data::train::Sample> samples) {
    Ptv3 model(pool, weights);
    Validation v;
    for (auto& s : samples) {
        const data::clicks::Mask object = data::clicks::mask_of(s.labels, 1);
        auto pred = predict_mask(model, s);
        v.iou1 += data::clicks::iou(object, pred);
        for (int k = 0; k < 2 && drawer.add_click(s, pred); ++k) pred = predict_mask(model, s);
        v.iou3 += data::clicks::iou(object, pred);
    }
    v.iou1 /= double(std::max<size_t>(samples.size(), 1));
    v.iou3 /= double(std::max<size_t>(samples.size(), 1));
    return v;
}

}  // namespace pg::nn::train

#include <algorithm>
#include <memory>

#include "dataset/clicks/mask.h"
#include "nn/train/training_task.h"

namespace pg::nn::train {

double accuracy(const std::vector<float>& logits, const std::vector<int32_t>& labels, int classes) {
    size_t right = 0, counted = 0;
    for (size_t i = 0; i < labels.size(); ++i) {
        if (labels[i] < 0 || labels[i] >= classes) continue;
        const float* row = &logits[i * size_t(classes)];
        right += int(std::max_element(row, row + classes) - row) == labels[i];
        ++counted;
    }
    return counted ? double(right) / double(counted) : 0.0;
}

std::vector<uint8_t> predict_mask(Ptv3& model, const data::train::Sample& s) {
    const auto out = model.forward(sample_input(s));
    std::vector<uint8_t> mask(s.size());
    for (size_t i = 0; i < s.size(); ++i) mask[i] = out.logits[2 * i + 1] > out.logits[2 * i];
    return mask;
}

Batch InteractiveTask::draw_batch(Trainer* trainer, data::Rng& rng, int batch, int max_clicks) const {
    Batch out;
    std::unique_ptr<Ptv3> model;  // made only when a sample needs it
    for (int b = 0; b < batch; ++b) {
        data::train::Sample s = drawer_.draw(rng);
        const int clicks = rng.below(max_clicks + 1);
        for (int k = 0; k < clicks; ++k) {
            if (!model) model = std::make_unique<Ptv3>(trainer->pool(), trainer->weights());
            if (!drawer_.add_click(s, predict_mask(*model, s))) break;
        }
        out.add(s);
    }
    return out;
}

Ptv3Input InteractiveTask::calibration_input(data::Rng& rng) const { return sample_input(drawer_.draw(rng)); }

bool InteractiveTask::prepare_validation(data::Rng& rng, int count) {
    val_samples_.clear();
    if (!val_drawer_) return false;
    for (int i = 0; i < count; ++i) val_samples_.push_back(val_drawer_->draw(rng));
    return true;
}

Validation InteractiveTask::validate(Pool& pool, const Ptv3Weights& weights) const {
    Ptv3 model(pool, weights);
    double iou1 = 0, iou3 = 0;
    for (data::train::Sample s : val_samples_) {
        const data::clicks::Mask object = data::clicks::mask_of(s.labels, 1);
        auto pred = predict_mask(model, s);
        iou1 += data::clicks::iou(object, pred);
        for (int k = 0; k < 2 && val_drawer_->add_click(s, pred); ++k) pred = predict_mask(model, s);
        iou3 += data::clicks::iou(object, pred);
    }
    const double n = double(std::max<size_t>(val_samples_.size(), 1));
    return {{{"iou1", iou1 / n}, {"iou3", iou3 / n}}};
}

nlohmann::json InteractiveTask::describe() const {
    return {{"task", "interactive"}, {"points", drawer_.options().max_points}, {"train_scenes", drawer_.scenes().size()}};
}

}  // namespace pg::nn::train

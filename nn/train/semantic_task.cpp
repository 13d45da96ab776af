#include <algorithm>

#include "nn/train/batch.h"
#include "nn/train/training_task.h"

namespace pg::nn::train {

namespace {

// A tile of a few Gaussians (a far floater's, the sky's) pools to a single voxel, which a
// training-mode BatchNorm cannot normalise; such tiles are redrawn (inference, with running
// statistics, takes them packed with others).
constexpr size_t kMinSamplePoints = 64;

data::train::SemanticSample draw_usable(const data::train::SemanticDrawer& drawer, data::Rng& rng) {
    data::train::SemanticSample s = drawer.draw(rng);
    for (int i = 0; i < 16 && s.size() < kMinSamplePoints; ++i) s = drawer.draw(rng);
    return s;
}

}  // namespace

Batch SemanticTask::draw_batch(Trainer*, data::Rng& rng, int batch, int) const {
    Batch out;
    for (int b = 0; b < batch; ++b) {
        const data::train::SemanticSample s = draw_usable(drawer_, rng);
        out.add(s.coord, s.feat, s.labels);
    }
    return out;
}

// Several tiles as one multi-cloud input of about a batch's points, as training steps see them.
Ptv3Input SemanticTask::calibration_input(data::Rng& rng) const {
    Batch out;
    while (out.labels.size() < drawer_.options().max_points) {
        const data::train::SemanticSample s = draw_usable(drawer_, rng);
        out.add(s.coord, s.feat, s.labels);
    }
    return out.input;
}

bool SemanticTask::prepare_validation(data::Rng& rng, int count) {
    val_samples_.clear();
    if (!val_drawer_) return false;
    for (int i = 0; i < count; ++i) val_samples_.push_back(val_drawer_->draw(rng));
    return true;
}

Validation SemanticTask::validate(Pool& pool, const Ptv3Weights& weights) const {
    Ptv3 model(pool, weights);
    const int k = weights.config().num_classes;
    std::vector<uint64_t> inter(size_t(k), 0), uni(size_t(k), 0), gt(size_t(k), 0);
    uint64_t right = 0, total = 0;
    for (const auto& s : val_samples_) {
        const auto out = model.forward(sample_input(s));
        for (size_t i = 0; i < s.size(); ++i) {
            const float* row = &out.logits[i * size_t(k)];
            const int p = int(std::max_element(row, row + k) - row), g = s.labels[i];
            if (g < 0 || g >= k) continue;
            ++total, ++gt[size_t(g)];
            if (p == g) ++right, ++inter[size_t(g)], ++uni[size_t(g)];
            else ++uni[size_t(g)], ++uni[size_t(p)];
        }
    }
    double miou = 0;
    int present = 0;
    for (int c = 0; c < k; ++c)
        if (gt[size_t(c)]) miou += double(inter[size_t(c)]) / double(uni[size_t(c)]), ++present;
    return {{{"miou", present ? miou / present : 0.0}, {"oa", total ? double(right) / double(total) : 0.0}}};
}

nlohmann::json SemanticTask::describe() const {
    return {{"task", "semantic"},
            {"points", drawer_.options().max_points},
            {"train_scenes", drawer_.scenes().size()},
            {"tile_size", drawer_.options().tile}};
}

}  // namespace pg::nn::train

#include "dataset/train/click_weights.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pg::data::train {

std::vector<float> click_weights(std::span<const glm::vec3> points, std::span<const TrainClick> clicks, float sigma) {
    if (!(sigma > 0)) throw std::invalid_argument("click_weights: sigma must be positive");
    // Float arithmetic in the shader's order, so training sees what inference computes.
    const float inv_two_sigma2 = 1.0f / (2.0f * sigma * sigma);
    std::vector<float> w(2 * points.size(), 0.0f);
    for (size_t i = 0; i < points.size(); ++i)
        for (const TrainClick& c : clicks) {
            const glm::vec3 d = points[i] - c.position;
            const float v = std::exp(-glm::dot(d, d) * inv_two_sigma2);
            float& channel = w[2 * i + (c.positive ? 0 : 1)];
            channel = std::max(channel, v);
        }
    return w;
}

}  // namespace pg::data::train

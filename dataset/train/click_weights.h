#pragma once
// The interactive model's input features: per point, the largest positive and the largest
// negative click weight w = exp(-|x - c|^2 / (2 sigma^2)), as the GPU prompt encoder
// computes them (shaders/segment/click_weights.comp). Points and clicks share one frame and
// sigma is in its units: in the RoiFrame, sigma = sigma_factor (the frame divides by scale).
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace pg::data::train {

struct TrainClick {
    glm::vec3 position{};   // in the sample's RoiFrame (before augmentation)
    bool positive = true;
    uint32_t gaussian = 0;  // the clicked Gaussian's scene index
};

// 2 floats per point (positive, negative); 0 in a channel without clicks.
std::vector<float> click_weights(std::span<const glm::vec3> points, std::span<const TrainClick> clicks, float sigma);

}  // namespace pg::data::train

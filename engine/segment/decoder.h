#pragma once
// The decoder interface: one batch of an object's ROI in, per-Gaussian foreground
// probability out. PTv3 implements it (nn/); the ground-truth decoder below is an evaluation
// tool that measures every other stage of the pipeline on its own.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "dataset/roi_frame.h"

namespace pg::seg {

struct DecoderBatch {
    std::vector<uint32_t> gaussians;   // scene indices
    std::vector<glm::vec3> coords;     // their centres
    std::vector<glm::vec2> features;   // positive and negative click weights
    std::vector<int32_t> click_gaussians;  // Gaussians hit by the object's positive clicks (-1: 3D click)
    data::RoiFrame frame;       // the object's frame: first positive anchor, scene up, object scale
};

class Decoder {
public:
    virtual ~Decoder() = default;
    virtual std::string name() const = 0;
    // P(foreground) for each Gaussian of the batch.
    virtual std::vector<float> predict(const DecoderBatch& batch) = 0;
};

// Reads the scene's own labels: foreground = the instance under the object's positive clicks.
// Clearly an evaluation tool: it only works on labelled (e.g. synthetic) scenes.
class GroundTruthDecoder : public Decoder {
public:
    explicit GroundTruthDecoder(std::vector<int32_t> labels) : labels_(std::move(labels)) {}
    std::string name() const override { return "ground-truth"; }
    std::vector<float> predict(const DecoderBatch& batch) override;

private:
    std::vector<int32_t> labels_;
};

}  // namespace pg::seg

#pragma once
// The semantic mode's ClassNetwork backed by PTv3 (nn/ptv3): a model whose config has the
// "tile" frame, its feature groups and class names. Lives in app/ because it joins
// engine/segment and nn, which do not depend on each other.
#include <memory>
#include <string>

#include "engine/segment/semantic_labeler.h"
#include "engine/vk/context.h"
#include "nn/ptv3/model.h"

namespace pg::app {

// The shipped semantic model: $PG_SEMANTIC_MODEL if set, else assets/models/semantic.safetensors
// found as default_model_path finds the interactive one. Empty if none exists.
std::string default_semantic_model_path();

class Ptv3ClassNetwork : public seg::ClassNetwork {
public:
    // InputError naming `option` when the file is unreadable, or is not a semantic model.
    Ptv3ClassNetwork(vk::Context& ctx, const std::string& model_path, const char* option = "--model");
    int classes() const override { return model_->config().num_classes; }
    double tile_size() const override { return model_->config().tile_size; }
    double voxel() const override { return model_->config().tile_size * model_->config().grid_size; }
    std::vector<std::string> features() const override { return model_->config().features; }
    std::vector<float> probabilities(const std::vector<seg::ClassCloud>& clouds) override;
    const nn::Ptv3Config& config() const { return model_->config(); }
    const std::string& path() const { return path_; }

private:
    std::string path_;
    std::shared_ptr<nn::Pool> pool_;
    std::unique_ptr<nn::Ptv3> model_;
};

}  // namespace pg::app

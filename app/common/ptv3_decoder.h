#pragma once
// The pipeline's Decoder backed by PTv3 (nn/ptv3): a batch's Gaussian centres and click
// weights in, plus the per-Gaussian feature groups the model's config lists (computed from the
// scene as training computes them), P(foreground) out, class 1 of the model being the clicked object. Lives in app/
// because it joins engine/segment and nn, which do not depend on each other.
#include <filesystem>
#include <memory>

#include "dataset/gaussian_cloud.h"
#include "engine/segment/decoder.h"
#include "nn/ptv3/model.h"

namespace pg::app {

// The shipped interactive model: $PG_MODEL if set, else assets/models/interactive.safetensors
// beside the binary's source tree (found from the executable's location, then from the source
// path it was built from). Empty if none exists.
std::string default_model_path();
// $env_var if set, else `relative` (to the repository root) found from the executable's location,
// then from the source path it was built from. Empty if none exists.
std::string shipped_file(const char* env_var, const std::filesystem::path& relative);

// A config argument: tiny / small / paper, or a model file whose config to take. InputError
// naming `option` otherwise.
nn::Ptv3Config ptv3_config_arg(const std::string& arg, const char* option);

// InputError naming `model_path` unless `c` is an interactive model: 2 classes, input channels
// the two click weights plus its feature groups'.
void check_interactive_config(const nn::Ptv3Config& c, const std::string& model_path);

class Ptv3Decoder : public seg::Decoder {
public:
    // `scene`: the cloud the batches index, needed (and kept by pointer) when the model reads
    // feature groups; set_scene changes it between scenes.
    Ptv3Decoder(vk::Context& ctx, const std::string& model_path, const data::GaussianCloud* scene = nullptr);
    void set_scene(const data::GaussianCloud* scene) { scene_ = scene; }
    std::string name() const override { return "ptv3 (" + path_ + ")"; }
    std::vector<float> predict(const seg::DecoderBatch& batch) override;
    const nn::Ptv3Config& config() const { return model_->config(); }

private:
    std::string path_;
    std::shared_ptr<nn::Pool> pool_;
    std::unique_ptr<nn::Ptv3> model_;
    const data::GaussianCloud* scene_ = nullptr;
};

}  // namespace pg::app

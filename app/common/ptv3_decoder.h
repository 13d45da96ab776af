#pragma once
// The pipeline's Decoder backed by PTv3 (nn/ptv3): a batch's Gaussian centres and click
// weights in, P(foreground) out, class 1 of the model being the clicked object. Lives in app/
// because it joins engine/segment and nn, which do not depend on each other.
#include <filesystem>
#include <memory>

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

class Ptv3Decoder : public seg::Decoder {
public:
    Ptv3Decoder(vk::Context& ctx, const std::string& model_path);
    std::string name() const override { return "ptv3 (" + path_ + ")"; }
    std::vector<float> predict(const seg::DecoderBatch& batch) override;
    const nn::Ptv3Config& config() const { return model_->config(); }

private:
    std::string path_;
    std::shared_ptr<nn::Pool> pool_;
    std::unique_ptr<nn::Ptv3> model_;
};

}  // namespace pg::app

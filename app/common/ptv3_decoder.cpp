#include "app/common/ptv3_decoder.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>

#include "dataset/error.h"
#include "dataset/semantic/gaussian_features.h"
#include "nn/safetensors.h"

namespace pg::app {

std::string shipped_file(const char* env_var, const std::filesystem::path& relative) {
    if (const char* env = std::getenv(env_var); env && *env) return env;
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec)  // build/app/pointgauss -> the repository root two folders up
        for (fs::path dir = exe.parent_path(); !dir.empty() && dir != dir.root_path(); dir = dir.parent_path())
            if (fs::exists(dir / relative)) return (dir / relative).string();
    const fs::path source = fs::path(PG_SOURCE_DIR) / relative;
    return fs::exists(source) ? source.string() : std::string();
}

std::string default_model_path() {
    return shipped_file("PG_MODEL", std::filesystem::path("assets") / "models" / "interactive.safetensors");
}

nn::Ptv3Config ptv3_config_arg(const std::string& arg, const char* option) {
    try {
        return nn::Ptv3Config::named(arg);
    } catch (const std::invalid_argument&) {
    }
    try {
        return nn::Ptv3Weights::config_of(nn::SafeTensors::load(arg));
    } catch (const nn::FormatError& e) {
        throw data::InputError(option, std::string(e.what()) + " (and it is not tiny, small or paper)");
    }
}

void check_interactive_config(const nn::Ptv3Config& c, const std::string& model_path) {
    if (c.semantic())
        throw data::InputError(model_path, "is a semantic model (classes " + std::to_string(c.num_classes) +
                                               ", no clicks): use it with segment --semantic");
    int feature_channels = 0;
    try {
        feature_channels = data::semantic::feature_channels(c.features);
    } catch (const std::invalid_argument& e) {
        throw data::InputError(model_path, e.what());
    }
    if (c.in_channels != 2 + feature_channels || c.num_classes != 2)
        throw data::InputError(model_path, "is not an interactive model (needs 2 input channels, positive and negative "
                                           "click weights, plus its feature groups' " +
                                               std::to_string(feature_channels) + ", and 2 classes; has " +
                                               std::to_string(c.in_channels) + " and " + std::to_string(c.num_classes) + ")");
}

Ptv3Decoder::Ptv3Decoder(vk::Context& ctx, const std::string& model_path, const data::GaussianCloud* scene)
    : path_(model_path), pool_(nn::Pool::create(ctx)), scene_(scene) {
    try {
        model_ = std::make_unique<nn::Ptv3>(*pool_, nn::Ptv3Weights::load(*pool_, model_path));
    } catch (const nn::FormatError& e) {
        throw data::InputError("--model", e.what());
    }
    check_interactive_config(model_->config(), model_path);
}

std::vector<float> Ptv3Decoder::predict(const seg::DecoderBatch& batch) {
    const size_t n = batch.coords.size();
    if (n == 0) return {};
    const auto& c = model_->config();
    std::vector<float> appearance;  // as dataset/train/sample_drawer.cpp: raw rows, then the voxel in this frame
    if (!c.features.empty()) {
        if (!scene_) throw std::logic_error("Ptv3Decoder: the model reads feature groups but has no scene");
        if (batch.gaussians.size() != n) throw std::logic_error("Ptv3Decoder: a batch without its Gaussians' indices");
        appearance = data::semantic::raw_gaussian_features(*scene_, batch.gaussians, c.features, batch.frame.up);
        const double unit = c.grid_size * batch.frame.scale;
        data::semantic::finish_gaussian_features(appearance, c.features, unit);
        data::semantic::raise_scale_spacing(appearance, c.features, batch.coords, unit, c.scale_spacing);
    }
    const size_t extra = appearance.size() / n;
    nn::Ptv3Input in;
    in.coord.reserve(3 * n);
    in.feat.reserve((2 + extra) * n);
    const bool roi_frame = c.input_frame == "roi";
    for (size_t i = 0; i < n; ++i) {
        const glm::vec3 p = roi_frame ? batch.frame.map(glm::dvec3(batch.coords[i])) : batch.coords[i];
        in.coord.insert(in.coord.end(), {p.x, p.y, p.z});
        in.feat.insert(in.feat.end(), {batch.features[i].x, batch.features[i].y});
        in.feat.insert(in.feat.end(), appearance.begin() + long(i * extra), appearance.begin() + long((i + 1) * extra));
    }
    const auto out = model_->forward(in);
    std::vector<float> p(n);
    for (size_t i = 0; i < n; ++i) {  // softmax over (background, foreground)
        const float l0 = out.logits[2 * i], l1 = out.logits[2 * i + 1];
        p[i] = 1.0f / (1.0f + std::exp(l0 - l1));
    }
    return p;
}

}  // namespace pg::app

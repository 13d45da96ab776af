#include "app/common/ptv3_decoder.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>

#include "dataset/error.h"
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

Ptv3Decoder::Ptv3Decoder(vk::Context& ctx, const std::string& model_path)
    : path_(model_path), pool_(nn::Pool::create(ctx)) {
    try {
        model_ = std::make_unique<nn::Ptv3>(*pool_, nn::Ptv3Weights::load(*pool_, model_path));
    } catch (const nn::FormatError& e) {
        throw data::InputError("--model", e.what());
    }
    const auto& c = model_->config();
    if (c.semantic())
        throw data::InputError(model_path, "is a semantic model (classes " + std::to_string(c.num_classes) +
                                               ", no clicks): use it with segment --semantic");
    if (c.in_channels != 2 || c.num_classes != 2)
        throw data::InputError(model_path, "is not an interactive model (needs 2 input channels: positive and "
                                           "negative click weights, and 2 classes; has " +
                                               std::to_string(c.in_channels) + " and " + std::to_string(c.num_classes) + ")");
}

std::vector<float> Ptv3Decoder::predict(const seg::DecoderBatch& batch) {
    const size_t n = batch.coords.size();
    if (n == 0) return {};
    nn::Ptv3Input in;
    in.coord.reserve(3 * n);
    in.feat.reserve(2 * n);
    const bool roi_frame = model_->config().input_frame == "roi";
    for (size_t i = 0; i < n; ++i) {
        const glm::vec3 p = roi_frame ? batch.frame.map(glm::dvec3(batch.coords[i])) : batch.coords[i];
        in.coord.insert(in.coord.end(), {p.x, p.y, p.z});
        in.feat.insert(in.feat.end(), {batch.features[i].x, batch.features[i].y});
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

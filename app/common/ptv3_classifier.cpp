#include "app/common/ptv3_classifier.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "app/common/ptv3_decoder.h"
#include "dataset/error.h"
#include "dataset/semantic/gaussian_features.h"
#include "nn/safetensors.h"

namespace pg::app {

std::string default_semantic_model_path() {
    return shipped_file("PG_SEMANTIC_MODEL", std::filesystem::path("assets") / "models" / "semantic.safetensors");
}

Ptv3ClassNetwork::Ptv3ClassNetwork(vk::Context& ctx, const std::string& model_path, const char* option)
    : path_(model_path), pool_(nn::Pool::create(ctx)) {
    try {
        model_ = std::make_unique<nn::Ptv3>(*pool_, nn::Ptv3Weights::load(*pool_, model_path));
    } catch (const nn::FormatError& e) {
        throw data::InputError(option, e.what());
    }
    const auto& c = model_->config();
    if (!c.semantic())
        throw data::InputError(model_path, "is not a semantic model (its input frame is '" + c.input_frame +
                                               "', with " + std::to_string(c.in_channels) +
                                               " input channels): --semantic needs a model trained on a semantic suite");
    int channels = 0;
    try {
        channels = data::semantic::feature_channels(c.features);
    } catch (const std::invalid_argument& e) {
        throw data::InputError(model_path, e.what());
    }
    if (channels != c.in_channels)
        throw data::InputError(model_path, "its feature groups give " + std::to_string(channels) +
                                               " channels, its network takes " + std::to_string(c.in_channels));
}

std::vector<float> Ptv3ClassNetwork::probabilities(const std::vector<seg::ClassCloud>& clouds) {
    nn::Ptv3Input in;
    for (const auto& c : clouds) {
        if (c.size() == 0) continue;
        in.coord.insert(in.coord.end(), c.coord.begin(), c.coord.end());
        in.feat.insert(in.feat.end(), c.feat.begin(), c.feat.end());
        in.offsets.push_back(int64_t(in.size()));
    }
    if (in.size() == 0) return {};
    if (in.offsets.size() == 1) in.offsets.clear();
    const int k = classes();
    std::vector<float> p = model_->forward(in).logits;
    for (size_t i = 0; i < in.size(); ++i) {
        float* row = &p[i * size_t(k)];
        const float top = *std::max_element(row, row + k);
        float sum = 0;
        for (int c = 0; c < k; ++c) sum += row[c] = std::exp(row[c] - top);
        for (int c = 0; c < k; ++c) row[c] /= sum;
    }
    return p;
}

}  // namespace pg::app

#include "nn/train/checkpoint.h"

#include <nlohmann/json.hpp>

#include "nn/safetensors.h"
#include "nn/train/trainer.h"

namespace pg::nn::train {
namespace {

void add_weights(std::vector<SafeTensorEntry>& entries, vk::Context& ctx, const Ptv3Weights& w,
                 const std::string& prefix) {
    for (const auto& [name, shape] : Ptv3Weights::expected(w.config()))
        entries.push_back(make_entry(prefix + name, "F32", shape, download_tensor<float>(ctx, w[name])));
}

}  // namespace

void save_model(const std::filesystem::path& path, Pool& pool, const Ptv3Weights& weights,
                const std::map<std::string, std::string>& metadata) {
    std::vector<SafeTensorEntry> entries;
    add_weights(entries, pool.context(), weights, "");
    std::map<std::string, std::string> meta = metadata;
    meta["config"] = weights.config().to_json().dump();
    write_safetensors(path, entries, meta);
}

void save_checkpoint(const std::filesystem::path& path, Trainer& trainer, int64_t step,
                     const std::map<std::string, std::string>& metadata) {
    std::vector<SafeTensorEntry> entries;
    vk::Context& ctx = trainer.pool().context();
    add_weights(entries, ctx, trainer.weights(), "model.");
    const AdamW& adam = trainer.optimizer();
    const auto& names = trainer.parameter_names();
    if (!adam.first_moments().empty()) {
        for (size_t i = 0; i < names.size(); ++i) {
            const Tensor& m = adam.first_moments()[i];
            entries.push_back(make_entry("adam_m." + names[i], "F32", m.shape, download_tensor<float>(ctx, m)));
            entries.push_back(
                make_entry("adam_v." + names[i], "F32", m.shape, download_tensor<float>(ctx, adam.second_moments()[i])));
        }
    }
    std::map<std::string, std::string> meta = metadata;
    meta["config"] = trainer.config().to_json().dump();
    meta["step"] = std::to_string(step);
    meta["adam_steps"] = std::to_string(adam.steps());
    write_safetensors(path, entries, meta);
}

Checkpoint load_checkpoint(const std::filesystem::path& path) {
    const SafeTensors file = SafeTensors::load(path);
    const std::string where = path.string();
    Checkpoint c;
    c.metadata = file.metadata();
    c.config = Ptv3Weights::config_of(file);
    if (!c.metadata.count("step")) throw FormatError(where, "not a training checkpoint (no 'step' in __metadata__)");
    try {
        c.step = std::stoll(c.metadata.at("step"));
    } catch (const std::exception&) {
        throw FormatError(where, "__metadata__ 'step' is not a number");
    }
    for (const auto& [name, shape] : Ptv3Weights::expected(c.config)) {
        if (!file.contains("model." + name)) throw FormatError(where, "missing tensor 'model." + name + "'");
        if (file.info("model." + name).shape != shape) throw FormatError(where, "tensor 'model." + name + "' has the wrong shape");
        c.weights[name] = file.f32("model." + name);
        const bool trainable = name.find("running_") == std::string::npos;
        if (trainable && file.contains("adam_m." + name)) {
            c.adam_m.push_back(file.f32("adam_m." + name));
            c.adam_v.push_back(file.f32("adam_v." + name));
            if (c.adam_m.back().size() != c.weights[name].size() || c.adam_v.back().size() != c.weights[name].size())
                throw FormatError(where, "optimizer state of '" + name + "' has the wrong size");
        }
    }
    return c;
}

void restore_optimizer(Trainer& trainer, const Checkpoint& c) {
    if (c.adam_m.empty()) return;  // saved before the first step
    if (c.adam_m.size() != trainer.parameter_names().size())
        throw FormatError("checkpoint", "optimizer state for " + std::to_string(c.adam_m.size()) + " of " +
                                            std::to_string(trainer.parameter_names().size()) + " parameters");
    Pool& pool = trainer.pool();
    std::vector<Tensor> m, v;
    const auto& names = trainer.parameter_names();
    for (size_t i = 0; i < names.size(); ++i) {
        const auto& shape = trainer.weights()[names[i]].shape;
        m.push_back(upload_tensor(pool, c.adam_m[i], shape, DType::F32));
        v.push_back(upload_tensor(pool, c.adam_v[i], shape, DType::F32));
    }
    int64_t adam_steps = c.step;
    if (c.metadata.count("adam_steps")) adam_steps = std::stoll(c.metadata.at("adam_steps"));
    trainer.optimizer().restore(std::move(m), std::move(v), adam_steps);
}

}  // namespace pg::nn::train

#include "nn/ptv3/weights.h"

#include <nlohmann/json.hpp>

#include "nn/safetensors.h"

namespace pg::nn {
namespace {

void add_linear(std::vector<std::pair<std::string, std::vector<int64_t>>>& v, const std::string& p, int64_t out,
                int64_t in, bool bias = true) {
    v.push_back({p + ".weight", {out, in}});
    if (bias) v.push_back({p + ".bias", {out}});
}
void add_norm(std::vector<std::pair<std::string, std::vector<int64_t>>>& v, const std::string& p, int64_t c,
              bool batch) {
    v.push_back({p + ".weight", {c}});
    v.push_back({p + ".bias", {c}});
    if (batch) {
        v.push_back({p + ".running_mean", {c}});
        v.push_back({p + ".running_var", {c}});
    }
}
void add_block(std::vector<std::pair<std::string, std::vector<int64_t>>>& v, const std::string& p, int64_t c,
               const Ptv3Config& cfg) {
    v.push_back({p + ".cpe.0.weight", {c, 3, 3, 3, c}});
    v.push_back({p + ".cpe.0.bias", {c}});
    add_linear(v, p + ".cpe.1", c, c);
    add_norm(v, p + ".cpe.2", c, false);
    add_norm(v, p + ".norm1.0", c, false);
    add_linear(v, p + ".attn.qkv", 3 * c, c, cfg.qkv_bias);
    add_linear(v, p + ".attn.proj", c, c);
    add_norm(v, p + ".norm2.0", c, false);
    add_linear(v, p + ".mlp.0.fc1", c * cfg.mlp_ratio, c);
    add_linear(v, p + ".mlp.0.fc2", c, c * cfg.mlp_ratio);
}

}  // namespace

std::vector<std::pair<std::string, std::vector<int64_t>>> Ptv3Weights::expected(const Ptv3Config& c) {
    std::vector<std::pair<std::string, std::vector<int64_t>>> v;
    v.push_back({"embedding.stem.conv.weight", {c.enc_channels[0], 5, 5, 5, c.in_channels}});
    add_norm(v, "embedding.stem.norm", c.enc_channels[0], true);
    for (int s = 0; s < c.stages(); ++s) {
        const std::string p = "enc.enc" + std::to_string(s);
        if (s > 0) {
            add_linear(v, p + ".down.proj", c.enc_channels[s], c.enc_channels[s - 1]);
            add_norm(v, p + ".down.norm.0", c.enc_channels[s], true);
        }
        for (int i = 0; i < c.enc_depths[s]; ++i) add_block(v, p + ".block" + std::to_string(i), c.enc_channels[s], c);
    }
    for (int s = c.stages() - 2; s >= 0; --s) {
        const std::string p = "dec.dec" + std::to_string(s);
        const int64_t in = s + 1 == c.stages() - 1 ? c.enc_channels.back() : c.dec_channels[s + 1];
        const int64_t out = c.dec_channels[s];
        add_linear(v, p + ".up.proj.0", out, in);
        add_norm(v, p + ".up.proj.1", out, true);
        add_linear(v, p + ".up.proj_skip.0", out, c.enc_channels[s]);
        add_norm(v, p + ".up.proj_skip.1", out, true);
        for (int i = 0; i < c.dec_depths[s]; ++i) add_block(v, p + ".block" + std::to_string(i), out, c);
    }
    add_linear(v, "head", c.num_classes, c.dec_channels[0]);
    return v;
}

std::string Ptv3Weights::canonical_name(std::string name) {
    for (const char* prefix : {"module.", "backbone."})
        if (name.rfind(prefix, 0) == 0) name = name.substr(std::string(prefix).size());
    for (const char* head : {"cls_head.0.", "seg_head.0.", "seg_head.", "cls_head."})
        if (name.rfind(head, 0) == 0) return "head." + name.substr(std::string(head).size());
    return name;
}

Ptv3Weights Ptv3Weights::load(Pool& pool, const std::filesystem::path& path) {
    return from_file(pool, SafeTensors::load(path));
}

Ptv3Config Ptv3Weights::config_of(const SafeTensors& file) {
    const std::string where = file.path().string();
    auto meta = file.metadata().find("config");
    if (meta == file.metadata().end())
        throw FormatError(where, "no PTv3 config in __metadata__ (convert PyTorch checkpoints with "
                                 "tools/convert_checkpoint.py)");
    try {
        return Ptv3Config::from_json(nlohmann::json::parse(meta->second));
    } catch (const std::exception& e) {
        throw FormatError(where, e.what());
    }
}

Ptv3Weights Ptv3Weights::from_file(Pool& pool, const SafeTensors& file) {
    return from_host(pool, config_of(file), host_values(file), file.path().string());
}

std::map<std::string, std::vector<float>> Ptv3Weights::host_values(const SafeTensors& file) {
    const std::string where = file.path().string();
    const Ptv3Config config = config_of(file);
    std::map<std::string, std::string> by_canonical;
    for (const auto& [name, info] : file.tensors()) {
        std::string c = canonical_name(name);
        if (c.find("num_batches_tracked") != std::string::npos) continue;
        if (!by_canonical.emplace(c, name).second)
            throw FormatError(where, "tensors '" + by_canonical[c] + "' and '" + name + "' name the same parameter");
    }
    std::map<std::string, std::vector<float>> values;
    for (const auto& [name, shape] : expected(config)) {
        auto it = by_canonical.find(name);
        if (it == by_canonical.end()) {
            if (name == "head.weight" || name == "head.bias")
                throw FormatError(where, "no head tensor (cls_head.0.* or seg_head.*)");
            throw FormatError(where, "missing tensor '" + name + "'");
        }
        const auto& info = file.info(it->second);
        if (info.shape != shape)
            throw FormatError(where, "tensor '" + it->second + "' has shape " + shape_string(info.shape) +
                                         ", the config needs " + shape_string(shape));
        values[name] = file.f32(it->second);
        by_canonical.erase(it);
    }
    if (!by_canonical.empty())
        throw FormatError(where, "unexpected tensor '" + by_canonical.begin()->second + "' for this config");
    return values;
}

Ptv3Weights Ptv3Weights::from_host(Pool& pool, const Ptv3Config& config,
                                   const std::map<std::string, std::vector<float>>& values, std::string source) {
    Ptv3Weights w;
    w.config_ = config;
    w.source_ = std::move(source);
    for (const auto& [name, shape] : expected(config)) {
        auto it = values.find(name);
        int64_t count = 1;
        for (int64_t d : shape) count *= d;
        if (it == values.end() || int64_t(it->second.size()) != count)
            throw FormatError(w.source_, "tensor '" + name + "' is missing or has the wrong size");
        if (name.find("running") == std::string::npos) w.parameters_ += count;
        w.tensors_[name] = upload_tensor(pool, it->second, shape, DType::F32);
    }
    return w;
}

const Tensor& Ptv3Weights::operator[](const std::string& name) const {
    auto it = tensors_.find(name);
    if (it == tensors_.end()) throw std::logic_error("PTv3 weights: no tensor " + name);
    return it->second;
}

}  // namespace pg::nn

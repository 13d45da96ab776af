#pragma once
// A PTv3 model file on the device: the config from __metadata__ and every tensor under its
// PyTorch name. Names are accepted as the release writes them (cls_head.*) and as Pointcept
// does (module.*, backbone.*, seg_head.*); they are stored without those prefixes and with
// the head as head.weight / head.bias.
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "nn/ptv3/config.h"
#include "nn/tensor.h"

namespace pg::nn {

class SafeTensors;

class Ptv3Weights {
public:
    // Reads `path`, checks that every tensor the config needs is there with the right shape,
    // and uploads them. Errors name the file and the tensor.
    static Ptv3Weights load(Pool& pool, const std::filesystem::path& path);
    static Ptv3Weights from_file(Pool& pool, const SafeTensors& file);
    // The config in a file's __metadata__ (FormatError naming the file if absent or invalid).
    static Ptv3Config config_of(const SafeTensors& file);
    // Every tensor the file's config needs, checked and converted to float, under canonical names.
    static std::map<std::string, std::vector<float>> host_values(const SafeTensors& file);
    // From host values under canonical names (all of expected(config), nothing else).
    static Ptv3Weights from_host(Pool& pool, const Ptv3Config& config,
                                 const std::map<std::string, std::vector<float>>& values, std::string source);

    const Ptv3Config& config() const { return config_; }
    const Tensor& operator[](const std::string& name) const;
    bool contains(const std::string& name) const { return tensors_.count(name) != 0; }
    long long parameter_count() const { return parameters_; }
    const std::string& source() const { return source_; }

    // The canonical name of a state_dict entry (prefixes stripped, head renamed).
    static std::string canonical_name(std::string name);
    // Every tensor the config needs with its shape, in state_dict order.
    static std::vector<std::pair<std::string, std::vector<int64_t>>> expected(const Ptv3Config& c);

private:
    Ptv3Config config_;
    std::map<std::string, Tensor> tensors_;
    long long parameters_ = 0;
    std::string source_;
};

}  // namespace pg::nn

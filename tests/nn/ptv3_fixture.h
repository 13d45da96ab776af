#pragma once
// A PTv3 golden fixture folder (the shared one of the release, or ours in tests/fixtures/ptv3):
// input.bin (coord f32 [N,3], feat f32 [N,C]), input.json, logits.bin, weights.safetensors,
// and optionally trace.safetensors.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "nn/ptv3/model.h"

namespace pg::test {

inline std::vector<float> read_f32_file(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::vector<char> raw((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::vector<float> v(raw.size() / 4);
    std::memcpy(v.data(), raw.data(), v.size() * 4);
    return v;
}

inline nn::Ptv3Input read_ptv3_input(const std::filesystem::path& dir, int channels, const char* name = "input") {
    std::vector<float> all = read_f32_file(dir / (std::string(name) + ".bin"));
    const size_t n = all.size() / size_t(3 + channels);
    nn::Ptv3Input in;
    in.coord.assign(all.begin(), all.begin() + long(3 * n));
    in.feat.assign(all.begin() + long(3 * n), all.end());
    std::ifstream js(dir / (std::string(name) + ".json"));
    if (js) {
        auto j = nlohmann::json::parse(js);
        if (j.contains("offsets") && j["offsets"].is_array()) in.offsets = j["offsets"].get<std::vector<int64_t>>();
    }
    return in;
}

// Largest |a - b| over the largest |b|: the agreement figure quoted for logits and stages.
inline double relative_max_error(const std::vector<float>& a, const std::vector<float>& b) {
    double diff = 0, scale = 1e-30;
    for (size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
        diff = std::max(diff, std::abs(double(a[i]) - double(b[i])));
        scale = std::max(scale, std::abs(double(b[i])));
    }
    return a.size() == b.size() ? diff / scale : INFINITY;
}

}  // namespace pg::test

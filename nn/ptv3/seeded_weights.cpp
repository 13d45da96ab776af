#include "nn/ptv3/seeded_weights.h"

#include <cmath>
#include <cstdint>

#include "nn/ptv3/weights.h"

namespace pg::nn {
namespace {

uint64_t fnv1a64(const std::string& s) {
    uint64_t h = 0xcbf29ce484222325ull;
    for (unsigned char ch : s) {
        h ^= ch;
        h *= 0x100000001b3ull;
    }
    return h;
}

uint64_t splitmix64(uint64_t z) {
    z += 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

bool ends_with(const std::string& s, const std::string& tail) {
    return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

}  // namespace

std::map<std::string, std::vector<float>> seeded_weights(const Ptv3Config& config) {
    std::map<std::string, std::vector<float>> out;
    const auto expected = Ptv3Weights::expected(config);
    std::map<std::string, size_t> rank;  // dims of each tensor, to find a bias's sibling weight
    for (const auto& [name, shape] : expected) rank[name] = shape.size();
    for (const auto& [name, shape] : expected) {
        // The release names the head cls_head.0.*; the hash uses the release's names.
        const std::string release = name.rfind("head.", 0) == 0 ? "cls_head.0." + name.substr(5) : name;
        int64_t count = 1, fan_in = 1;
        for (size_t d = 0; d < shape.size(); ++d) {
            count *= shape[d];
            if (d > 0) fan_in *= shape[d];
        }
        const bool is_bias = ends_with(name, ".bias");
        const size_t sibling_rank = is_bias ? rank[name.substr(0, name.size() - 5) + ".weight"] : 0;
        const double dense_scale = 1.0 / std::sqrt(double(fan_in));
        const uint64_t h = fnv1a64(release);
        std::vector<float> v(static_cast<size_t>(count));
        for (int64_t i = 0; i < count; ++i) {
            const double u = double(splitmix64(h ^ (uint64_t(i) * 0x9E3779B97F4A7C15ull)) >> 40) / 16777216.0;
            const double s = 2 * u - 1;
            double value;
            if (ends_with(name, "running_mean")) value = 0.1 * s;
            else if (ends_with(name, "running_var")) value = 0.5 + u;
            else if (is_bias) value = sibling_rank >= 2 ? s * 0.02 : 0.05 * s;
            else if (shape.size() >= 2) value = s * dense_scale;
            else value = 1.0 + 0.1 * s;
            v[size_t(i)] = float(value);
        }
        out[name] = std::move(v);
    }
    return out;
}

}  // namespace pg::nn

#include "nn/train/initial_weights.h"

#include <cmath>
#include <random>

#include "nn/ptv3/weights.h"

namespace pg::nn::train {
namespace {

bool ends_with(const std::string& s, const std::string& tail) {
    return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

}  // namespace

std::map<std::string, std::vector<float>> initial_weights(const Ptv3Config& config, uint64_t seed) {
    std::mt19937_64 rng(seed);
    const auto expected = Ptv3Weights::expected(config);
    std::map<std::string, std::vector<int64_t>> shapes(expected.begin(), expected.end());
    std::map<std::string, std::vector<float>> values;
    for (const auto& [name, shape] : expected) {
        int64_t count = 1;
        for (int64_t d : shape) count *= d;
        std::vector<float> v(static_cast<size_t>(count), 0.0f);
        const bool norm = name.find("norm") != std::string::npos || name.find("cpe.2") != std::string::npos ||
                          name.find("proj.1") != std::string::npos || name.find("proj_skip.1") != std::string::npos;
        if (ends_with(name, "running_var")) {
            std::fill(v.begin(), v.end(), 1.0f);
        } else if (ends_with(name, "running_mean")) {
        } else if (norm) {
            if (ends_with(name, ".weight")) std::fill(v.begin(), v.end(), 1.0f);
        } else {
            // fan_in of the layer: the weight's elements per output row (a bias takes its weight's).
            const std::string weight = ends_with(name, ".bias") ? name.substr(0, name.size() - 5) + ".weight" : name;
            const std::vector<int64_t>& ws = shapes.at(weight);
            int64_t fan_in = 1;
            for (size_t i = 1; i < ws.size(); ++i) fan_in *= ws[i];
            const double bound = 1.0 / std::sqrt(double(fan_in));
            std::uniform_real_distribution<double> u(-bound, bound);
            for (float& x : v) x = float(u(rng));
        }
        values[name] = std::move(v);
    }
    return values;
}

}  // namespace pg::nn::train

#pragma once
// Fresh PTv3 weights for training, initialised as PyTorch's layers initialise themselves
// (Pointcept's PTv3 adds no init of its own): Linear and sparse conv weights and biases uniform
// in +-1/sqrt(fan_in) (kaiming_uniform with a = sqrt(5)), norm weights 1, biases 0, running
// mean 0 and variance 1.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "nn/ptv3/config.h"

namespace pg::nn::train {

// Values under canonical names (Ptv3Weights::from_host takes them). Deterministic per seed.
std::map<std::string, std::vector<float>> initial_weights(const Ptv3Config& config, uint64_t seed);

}  // namespace pg::nn::train

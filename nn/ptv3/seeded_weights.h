#pragma once
// Deterministic pseudo-random PTv3 weights, element by element from a hash of the tensor's
// release name and index, so a paper-size model (185 MB) can be rebuilt anywhere instead
// of stored: `bench ptv3` uses it, and the paper-config golden fixture
// (tests/fixtures/ptv3/paper, tools/make_ptv3_fixtures.py) is defined by it.
#include <map>
#include <string>
#include <vector>

#include "nn/ptv3/config.h"

namespace pg::nn {

// Values under canonical names (see Ptv3Weights::canonical_name).
std::map<std::string, std::vector<float>> seeded_weights(const Ptv3Config& config);

}  // namespace pg::nn

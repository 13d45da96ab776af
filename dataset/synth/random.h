#pragma once
// The synthetic scenes draw from the project's portable generator (dataset/random.h).
#include "dataset/random.h"

namespace pg::data::synth {
using pg::data::derive_seed;
using pg::data::mix64;
using pg::data::Rng;
}  // namespace pg::data::synth

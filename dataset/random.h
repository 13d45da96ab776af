#pragma once
// Deterministic random numbers: splitmix64 with our own mappings
// to floats, so a seed gives the same scene on every platform and standard library
// (std::*_distribution is implementation-defined).
#include <cmath>
#include <cstdint>

namespace pg::data {

// One splitmix64 step, also used to hash seeds and lattice coordinates.
constexpr uint64_t mix64(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

// A seed for a sub-stream (a shape, a camera ring, ...) from a parent seed and a key.
constexpr uint64_t derive_seed(uint64_t seed, uint64_t key) {
    return mix64(seed * 0x9E3779B97F4A7C15ull + mix64(key + 0x632BE59BD9B4E019ull));
}

class Rng {
public:
    explicit Rng(uint64_t seed) : state_(mix64(seed ^ 0xD1B54A32D192ED03ull)) {}
    uint64_t next() { return mix64(state_ += 0x9E3779B97F4A7C15ull); }
    // Uniform in [0, 1) with 53 random bits.
    double uniform() { return double(next() >> 11) * (1.0 / 9007199254740992.0); }
    double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
    // Uniform integer in [0, n).
    int below(int n) { return n <= 1 ? 0 : int((next() >> 33) % uint64_t(n)); }
    int between(int lo, int hi) { return lo + below(hi - lo + 1); }  // inclusive
    bool chance(double p) { return uniform() < p; }
    double sign() { return chance(0.5) ? 1.0 : -1.0; }
    // Standard normal by Box-Muller (one value per call; the pair's twin is dropped).
    double normal() {
        const double u1 = 1.0 - uniform();
        return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * uniform());
    }
    double normal(double mean, double sd) { return mean + sd * normal(); }

private:
    uint64_t state_;
};

}  // namespace pg::data

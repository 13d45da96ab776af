#pragma once
// Small host<->device helpers the gradient tests share.
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "nn/tensor.h"

namespace pg::test {

inline nn::Tensor up(nn::Pool& pool, const std::vector<float>& v, std::vector<int64_t> shape) {
    return nn::upload_tensor(pool, v, std::move(shape), nn::DType::F32);
}

inline std::vector<float> down(nn::Pool& pool, const nn::Tensor& t) {
    return nn::download_tensor<float>(pool.context(), t);
}

// Bit-identical results: the determinism the backward passes promise.
inline bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

// Class labels in [0, K) for M rows, about `ignored` of them -1 (the losses' ignored label).
inline std::vector<int32_t> random_labels(size_t M, int32_t K, double ignored, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<int32_t> v(M);
    for (auto& l : v) l = u(rng) < ignored ? -1 : int32_t(rng() % uint32_t(K));
    return v;
}

}  // namespace pg::test

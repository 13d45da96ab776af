#pragma once
// Small host<->device helpers the gradient tests share.
#include <cstring>
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

}  // namespace pg::test

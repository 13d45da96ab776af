#pragma once
// PTv3's normalisation epsilons (Pointcept: BatchNorm1d eps=1e-3, LayerNorm default).

namespace pg::nn {

constexpr float kBatchNormEps = 1e-3f;
constexpr float kLayerNormEps = 1e-5f;

}  // namespace pg::nn

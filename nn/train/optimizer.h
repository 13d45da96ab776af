#pragma once
// AdamW (PyTorch's torch.optim.AdamW: decoupled weight decay, bias-corrected moments, eps
// after the bias-corrected square root) on device tensors, and the OneCycle learning-rate and
// beta1 schedule of torch.optim.lr_scheduler.OneCycleLR that the release trains with.
#include <cstdint>
#include <vector>

#include "nn/tensor.h"

namespace pg::nn::train {

struct AdamWOptions {
    double beta2 = 0.999, eps = 1e-8, weight_decay = 0.05;
};

// Moments per parameter tensor, zero-initialised on first use.
class AdamW {
public:
    AdamW(Pool& pool, AdamWOptions options = {}) : pool_(pool), options_(options) {}
    // One step over all parameters with their gradients (same shapes, f32); `lr` and `beta1`
    // come from the schedule. Records into cmd; parameters are updated in place.
    void step(vk::CommandList& cmd, const std::vector<Tensor>& params, const std::vector<Tensor>& grads, double lr,
              double beta1);
    int64_t steps() const { return step_; }
    // Moments for checkpoints: m and v of parameter i.
    const std::vector<Tensor>& first_moments() const { return m_; }
    const std::vector<Tensor>& second_moments() const { return v_; }
    void restore(std::vector<Tensor> m, std::vector<Tensor> v, int64_t steps);

private:
    Pool& pool_;
    AdamWOptions options_;
    std::vector<Tensor> m_, v_;
    int64_t step_ = 0;
};

// OneCycleLR(max_lr, total_steps, pct_start, anneal cos, div_factor, final_div_factor,
// cycle_momentum with base 0.85 / max 0.95), two phases, as PyTorch computes it.
struct OneCycle {
    double max_lr = 1e-3;
    int64_t total_steps = 1;
    double pct_start = 0.05, div_factor = 10, final_div_factor = 1000;
    double base_momentum = 0.85, max_momentum = 0.95;
    double lr(int64_t step) const;
    double beta1(int64_t step) const;
};

}  // namespace pg::nn::train

#include "nn/train/optimizer.h"

#include <cmath>
#include <stdexcept>

#include "shaders/nn/grad_shared.glsl"

namespace pg::nn::train {
namespace {

// PyTorch's _annealing_cos: from `start` at pct 0 to `end` at pct 1.
double anneal_cos(double start, double end, double pct) { return end + (start - end) / 2.0 * (std::cos(M_PI * pct) + 1); }

// Phase and position of `step`: PyTorch ends phase one at pct_start * total - 1 and phase two at total - 1.
template <class F> double one_cycle(const OneCycle& s, int64_t step, F value) {
    const double end1 = s.pct_start * double(s.total_steps) - 1, end2 = double(s.total_steps) - 1;
    const double t = double(std::min<int64_t>(std::max<int64_t>(step, 0), s.total_steps - 1));
    if (t <= end1) return value(0, end1 > 0 ? t / end1 : 1.0);
    return value(1, end2 > end1 ? (t - end1) / (end2 - end1) : 1.0);
}

}  // namespace

void AdamW::step(vk::CommandList& cmd, const std::vector<Tensor>& params, const std::vector<Tensor>& grads, double lr,
                 double beta1) {
    if (params.size() != grads.size()) throw std::invalid_argument("AdamW: one gradient per parameter is needed");
    if (m_.empty())
        for (const Tensor& p : params) {
            m_.push_back(pool_.empty(p.shape, DType::F32));
            v_.push_back(pool_.empty(p.shape, DType::F32));
            cmd.fill(*m_.back().buffer, 0);
            cmd.fill(*v_.back().buffer, 0);
        }
    if (m_.size() != params.size()) throw std::invalid_argument("AdamW: the parameter list changed between steps");
    ++step_;
    // As PyTorch: the current beta1 (which the schedule cycles) to the power of the step count.
    const double bias1 = 1 - std::pow(beta1, double(step_)), bias2 = 1 - std::pow(options_.beta2, double(step_));
    for (size_t i = 0; i < params.size(); ++i) {
        if (params[i].shape != grads[i].shape || params[i].dtype != DType::F32 || grads[i].dtype != DType::F32)
            throw std::invalid_argument("AdamW: gradient " + std::to_string(i) + " has shape " + grads[i].shape_string() +
                                        ", its parameter " + params[i].shape_string());
        const uint32_t n = uint32_t(params[i].numel());
        const grad::gpu::AdamWPush push{n, float(lr), float(beta1), float(options_.beta2), float(options_.eps),
                                        float(options_.weight_decay), float(bias1), float(std::sqrt(bias2))};
        cmd.dispatch("nn/adamw", {params[i], grads[i], m_[i], v_[i]}, push, vk::ceil_div(n, PG_GRAD_THREADS));
    }
}

void AdamW::restore(std::vector<Tensor> m, std::vector<Tensor> v, int64_t steps) {
    m_ = std::move(m);
    v_ = std::move(v);
    step_ = steps;
}

double OneCycle::lr(int64_t step) const {
    const double initial = max_lr / div_factor, minimum = initial / final_div_factor;
    return one_cycle(*this, step, [&](int phase, double pct) {
        return phase == 0 ? anneal_cos(initial, max_lr, pct) : anneal_cos(max_lr, minimum, pct);
    });
}

double OneCycle::beta1(int64_t step) const {
    return one_cycle(*this, step, [&](int phase, double pct) {
        return phase == 0 ? anneal_cos(max_momentum, base_momentum, pct) : anneal_cos(base_momentum, max_momentum, pct);
    });
}

}  // namespace pg::nn::train

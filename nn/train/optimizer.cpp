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
    for (size_t i = 0; i < params.size(); ++i)
        if (params[i].shape != grads[i].shape || params[i].dtype != DType::F32 || grads[i].dtype != DType::F32)
            throw std::invalid_argument("AdamW: gradient " + std::to_string(i) + " has shape " + grads[i].shape_string() +
                                        ", its parameter " + params[i].shape_string());
    // PG_ADAMW_SETS tensors per dispatch: on CPU devices each dispatch's fixed cost outweighs a
    // small tensor's update.
    constexpr size_t kSets = PG_ADAMW_SETS;
    static_assert(7 * kSets == 28, "nn/adamw binds 7 buffers per tensor, 28 in all");
    // Empty tensors have nothing to update (and no texel to view).
    std::vector<size_t> live;
    for (size_t i = 0; i < params.size(); ++i)
        if (params[i].numel() > 0) live.push_back(i);
    for (size_t first = 0; first < live.size(); first += kSets) {
        grad::gpu::AdamWPush push{};
        push.lr = float(lr), push.beta1 = float(beta1), push.beta2 = float(options_.beta2);
        push.eps = float(options_.eps), push.weight_decay = float(options_.weight_decay);
        push.bias1 = float(bias1), push.bias2_sqrt = float(std::sqrt(bias2));
        std::vector<vk::BufferRange> bind;
        bind.reserve(7 * kSets);
        uint32_t groups = 0;
        for (size_t s = 0; s < kSets; ++s) {
            const size_t i = live[first + s < live.size() ? first + s : first];  // unused sets: set 0's buffers
            // Read views of p, g, m, v, then p, m, v written (nn/adamw).
            for (const Tensor* t : std::initializer_list<const Tensor*>{&params[i], &grads[i], &m_[i], &v_[i],
                                                                          &params[i], &m_[i], &v_[i]})
                bind.push_back(*t);
            push.first_group[s] = groups;
            if (first + s >= live.size()) continue;
            push.count[s] = uint32_t(params[i].numel());
            groups += vk::ceil_div(push.count[s], PG_GRAD_THREADS);
        }
        for (size_t s = 0; s < kSets; ++s)
            if (first + s >= live.size()) push.first_group[s] = groups;
        cmd.dispatch("nn/adamw", bind, push, groups);
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

#pragma once
// A training step being recorded: the stream and the weights the modules record with, the
// BatchNorm momentum and drop path they train with, the tape their forwards leave for their
// backwards, and the parameter gradients their backwards write.
#include <map>
#include <random>
#include <string>

#include "nn/ptv3/tape.h"
#include "nn/ptv3/weights.h"
#include "nn/tensor.h"

namespace pg::nn {

class TrainingPass {
public:
    // bn_momentum: the running statistics' update; drop_path: the deepest block's rate (0: off),
    // masks drawn from rng.
    TrainingPass(vk::CommandList& cmd, Pool& pool, const Ptv3Weights& weights, double bn_momentum, double drop_path,
                 std::mt19937_64& rng)
        : cmd(cmd), pool(pool), weights(weights), bn_momentum(bn_momentum), drop_path(drop_path), rng_(rng) {}

    vk::CommandList& cmd;
    Pool& pool;
    const Ptv3Weights& weights;
    const double bn_momentum, drop_path;
    Ptv3Tape tape;
    std::map<std::string, Tensor> grads;  // by canonical parameter name

    // Weights by prefix: p.weight, p.bias (bias = false: none). The backward takes the forward's
    // input, writes the parameters' gradients and returns the input's.
    Tensor linear(const Tensor& x, const std::string& p, bool bias = true);
    Tensor linear_backward(const Tensor& x, const std::string& p, const Tensor& dy, bool bias = true);
    // With a residual, residual + LayerNorm(x) (its gradient is dy itself).
    Tensor layer_norm(const Tensor& x, const std::string& p, const Tensor& residual = {});
    Tensor layer_norm_backward(const Tensor& x, const std::string& p, const Tensor& dy);

    // Per-point drop path: a keep mask for `rows` rows at this rate (undefined when 0), drawn now.
    Tensor keep_mask(int64_t rows, double rate);
    // x + branch, the branch's rows scaled by the keep mask when there is one.
    Tensor residual(const Tensor& x, const Tensor& branch, const Tensor& keep);
    // The gradient of the branch of `residual` from the gradient of its sum.
    Tensor through_keep(const Tensor& dy, const Tensor& keep);

private:
    std::mt19937_64& rng_;
};

}  // namespace pg::nn

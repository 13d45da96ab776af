#pragma once
// An inference forward being recorded: the stream and the weights the modules record with, the
// trace they report to, and the work they count (Ptv3Output::flops, pass timings).
#include <string>
#include <vector>

#include "nn/ops/linear.h"
#include "nn/ops/sparse_conv.h"
#include "nn/ptv3/model.h"

namespace pg::nn {

class InferencePass {
public:
    InferencePass(vk::CommandList& cmd, Pool& pool, const Ptv3Weights& weights, const Ptv3Trace& trace,
                  Ptv3Output& out)
        : cmd(cmd), pool(pool), weights(weights), trace_(trace), out_(out) {}

    vk::CommandList& cmd;
    Pool& pool;
    const Ptv3Weights& weights;

    bool tracing() const { return bool(trace_); }
    // Hands t to the trace (waiting for the stream first); nothing without one.
    void emit(const std::string& name, const Tensor& t);
    // Submits what was recorded, waits, and keeps the passes' timings.
    void sync();

    // Weights by prefix: p.weight, p.bias (bias = false: none).
    Tensor linear(const Tensor& x, const std::string& p, const Tensor& residual = {},
                  ops::Activation act = ops::Activation::None, bool bias = true);
    Tensor layer_norm(const Tensor& x, const std::string& p, const Tensor& residual = {});
    Tensor batch_norm_gelu(const Tensor& x, const std::string& p);
    // `rules`: nbr's rulebook where the level keeps one; without, sparse_conv builds one if it uses it.
    Tensor conv(const Tensor& x, const Tensor& nbr, const Tensor& w, const Tensor& b,
                const ops::Rulebook* rules = nullptr);
    void count_attention(double flops) { out_.flops["attention"] += flops; }
    // After the final sync: the convolutions' multiply-adds over their existing neighbour pairs
    // into Ptv3Output::flops (downloads the maps).
    void count_conv_pairs();

private:
    struct ConvUse {
        Tensor nbr;
        int64_t cin, cout;
    };
    const Ptv3Trace& trace_;
    Ptv3Output& out_;
    std::vector<ConvUse> convs_;
};

}  // namespace pg::nn

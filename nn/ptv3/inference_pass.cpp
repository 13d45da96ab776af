#include "nn/ptv3/inference_pass.h"

#include "nn/ops/norm.h"
#include "nn/ptv3/norm_constants.h"

namespace pg::nn {

void InferencePass::emit(const std::string& name, const Tensor& t) {
    if (!trace_) return;
    sync();
    trace_(name, t);
}

void InferencePass::sync() {
    cmd.submit_and_wait();
    for (const auto& p : cmd.timings()) out_.passes.push_back(p);
}

Tensor InferencePass::linear(const Tensor& x, const std::string& p, const Tensor& residual, ops::Activation act,
                             bool bias) {
    const Tensor& w = weights[p + ".weight"];
    out_.flops["linear"] += 2.0 * double(x.dim(0)) * double(w.dim(0)) * double(w.dim(1));
    cmd.begin_pass("linear");
    return ops::linear(cmd, pool, x, w, bias ? weights[p + ".bias"] : Tensor{}, residual, act);
}

Tensor InferencePass::layer_norm(const Tensor& x, const std::string& p, const Tensor& residual) {
    cmd.begin_pass("norm");
    return ops::layer_norm(cmd, pool, x, weights[p + ".weight"], weights[p + ".bias"], kLayerNormEps, residual);
}

Tensor InferencePass::batch_norm_gelu(const Tensor& x, const std::string& p) {
    cmd.begin_pass("norm");
    return ops::batch_norm(cmd, pool, x, weights[p + ".running_mean"], weights[p + ".running_var"],
                           weights[p + ".weight"], weights[p + ".bias"], kBatchNormEps, true);
}

Tensor InferencePass::conv(const Tensor& x, const Tensor& nbr, const Tensor& w, const Tensor& b,
                           const ops::Rulebook* rules) {
    convs_.push_back({nbr, x.dim(1), w.dim(0)});
    cmd.begin_pass("conv");
    return rules ? ops::sparse_conv(cmd, pool, x, *rules, w, b) : ops::sparse_conv(cmd, pool, x, nbr, w, b);
}

void InferencePass::count_conv_pairs() {
    for (const auto& u : convs_) {
        double pairs = 0;
        for (int32_t v : download_tensor<int32_t>(pool.context(), u.nbr)) pairs += v >= 0;
        out_.flops["sparse_conv"] += 2.0 * pairs * double(u.cin) * double(u.cout);
    }
}

}  // namespace pg::nn

#include "nn/ptv3/embedding.h"

#include "nn/ops/elementwise.h"
#include "nn/ops/sparse_conv.h"
#include "nn/ptv3/inference_pass.h"
#include "nn/ptv3/training_pass.h"
#include "nn/train/grad_ops.h"

namespace pg::nn {
namespace {

const std::string kConv = "embedding.stem.conv.weight";

}  // namespace

Embedding::Embedding(const Ptv3Config& c) : in_channels_(c.in_channels), channels_(c.enc_channels[0]) {}

Tensor Embedding::conv_weight(const Ptv3Weights& weights) const {
    return reshaped(weights[kConv], {channels_, 125 * in_channels_});
}

void Embedding::forward(InferencePass& pass, Ptv3Point& point) const {
    const Ptv3Structure& st = *point.structure;
    pass.cmd.begin_pass("elementwise");
    Tensor x = ops::gather_rows(pass.cmd, pass.pool, point.feat, st.vox.first);
    x = pass.conv(x, st.nbr5, conv_weight(pass.weights), Tensor{});
    pass.emit("embedding.stem.conv/feat", x);
    point.feat = norm_.forward(pass, x);
    pass.emit("embedding/feat", point.feat);
}

void Embedding::forward(TrainingPass& pass, Ptv3Point& point) const {
    const Ptv3Structure& st = *point.structure;
    Tape& t = pass.tape.embedding;
    pass.cmd.begin_pass("conv");
    t.x = ops::gather_rows(pass.cmd, pass.pool, point.feat, st.vox.first);
    Tensor x = ops::sparse_conv(pass.cmd, pass.pool, t.x, st.nbr5, conv_weight(pass.weights), Tensor{});
    point.feat = norm_.forward(pass, t.norm, x);
}

void Embedding::backward(TrainingPass& pass, Ptv3Point& grad) const {
    const Tape& t = pass.tape.embedding;
    Tensor d = norm_.backward(pass, t.norm, grad.feat);
    pass.cmd.begin_pass("conv bwd");
    // The input features take no gradient: dw alone.
    grad::ConvGrads g = grad::sparse_conv_backward(pass.cmd, pass.pool, t.x, grad.structure->nbr5,
                                                   conv_weight(pass.weights), d, false);
    pass.grads[kConv] = reshaped(g.dw, pass.weights[kConv].shape);
    grad.feat = {};
}

}  // namespace pg::nn

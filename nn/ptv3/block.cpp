#include "nn/ptv3/block.h"

#include <algorithm>
#include <cmath>

#include "nn/ops/attention.h"
#include "nn/ops/elementwise.h"
#include "nn/ptv3/inference_pass.h"
#include "nn/ptv3/training_pass.h"
#include "nn/train/grad_attention.h"
#include "nn/train/grad_ops.h"

namespace pg::nn {
namespace {

// x + branch: `branch` gets x as the residual to fuse into its last op, except when tracing,
// where the trace sees the branch alone (under `name`) before the add.
template <class Branch>
Tensor add_branch(InferencePass& pass, const Tensor& x, const std::string& name, Branch branch) {
    if (!pass.tracing()) return branch(x);
    const Tensor h = branch(Tensor{});
    pass.emit(name, h);
    return ops::add(pass.cmd, pass.pool, x, h);
}

}  // namespace

Block::Block(const Ptv3Config& c, std::string name, int channels, int heads, int patch, int index, int drop_slot,
             int drop_slots)
    : name_(std::move(name)), channels_(channels), heads_(heads), patch_(patch), index_(index), drop_slot_(drop_slot),
      drop_slots_(drop_slots), qkv_bias_(c.qkv_bias),
      scale_(c.qk_scale > 0 ? float(c.qk_scale) : 1.0f / std::sqrt(float(channels / heads))) {}

Tensor Block::cpe_weight(const Ptv3Weights& weights) const {
    return reshaped(weights[name_ + ".cpe.0.weight"], {channels_, 27 * channels_});
}

double Block::drop_rate(double deepest) const {
    return drop_slots_ > 1 ? deepest * drop_slot_ / (drop_slots_ - 1) : 0.0;
}

void Block::forward(InferencePass& pass, Ptv3Point& point) const {
    const std::string& p = name_;
    const Ptv3Weights& W = pass.weights;
    const Ptv3Level& L = point.at();
    Tensor x = point.feat;
    Tensor h = pass.conv(point.conv_feat.defined() ? point.conv_feat : x, L.nbr3, cpe_weight(W),
                         W[p + ".cpe.0.bias"], &L.rules3);
    pass.emit(p + ".cpe.0/feat", h);
    h = pass.linear(h, p + ".cpe.1");
    pass.emit(p + ".cpe.1/feat", h);
    x = add_branch(pass, x, p + ".cpe/feat", [&](const Tensor& residual) {
        const Tensor y = pass.layer_norm(h, p + ".cpe.2", residual);
        pass.emit(p + ".cpe.2/feat", y);
        return y;
    });
    h = pass.layer_norm(x, p + ".norm1.0");
    pass.emit(p + ".norm1/feat", h);
    Tensor qkv = pass.linear(h, p + ".attn.qkv", {}, ops::Activation::None, qkv_bias_);
    pass.cmd.begin_pass("attention");
    for (size_t b = 0; b + 1 < L.offsets_host.size(); ++b) {
        const double nb = L.offsets_host[b + 1] - L.offsets_host[b];
        pass.count_attention(4.0 * channels_ * nb * std::min<double>(nb, patch_));
    }
    h = ops::window_attention(pass.cmd, pass.pool, qkv, L.order_for_block(index_), L.offsets, heads_, patch_, scale_);
    x = add_branch(pass, x, p + ".attn/feat",
                   [&](const Tensor& residual) { return pass.linear(h, p + ".attn.proj", residual); });
    h = pass.layer_norm(x, p + ".norm2.0");
    pass.emit(p + ".norm2/feat", h);
    h = pass.linear(h, p + ".mlp.0.fc1", {}, ops::Activation::Gelu);
    x = add_branch(pass, x, p + ".mlp/feat",
                   [&](const Tensor& residual) { return pass.linear(h, p + ".mlp.0.fc2", residual); });
    pass.emit(p + "/feat", x);
    point.feat = x;
    point.conv_feat = {};
}

void Block::forward(TrainingPass& pass, Ptv3Point& point) const {
    const std::string& p = name_;
    const Ptv3Weights& W = pass.weights;
    const Ptv3Level& L = point.at();
    const double rate = drop_rate(pass.drop_path);
    Tape& t = pass.tape.blocks.emplace_back();
    t.separate_cpe_input = point.conv_feat.defined();
    t.cpe_in = t.separate_cpe_input ? point.conv_feat : point.feat;
    pass.cmd.begin_pass("conv");
    t.h1 = ops::sparse_conv(pass.cmd, pass.pool, t.cpe_in, L.rules3, cpe_weight(W), W[p + ".cpe.0.bias"]);
    t.h2 = pass.linear(t.h1, p + ".cpe.1");
    t.x1 = pass.layer_norm(t.h2, p + ".cpe.2", point.feat);
    t.n1 = pass.layer_norm(t.x1, p + ".norm1.0");
    t.qkv = pass.linear(t.n1, p + ".attn.qkv", qkv_bias_);
    pass.cmd.begin_pass("attention");
    t.a = ops::window_attention(pass.cmd, pass.pool, t.qkv, L.order_for_block(index_), L.offsets, heads_, patch_,
                                scale_);
    t.keep_attn = pass.keep_mask(L.n, rate);
    t.x2 = pass.residual(t.x1, pass.linear(t.a, p + ".attn.proj"), t.keep_attn);
    t.n2 = pass.layer_norm(t.x2, p + ".norm2.0");
    t.pre = pass.linear(t.n2, p + ".mlp.0.fc1");
    pass.cmd.begin_pass("elementwise");
    t.f1 = ops::gelu(pass.cmd, pass.pool, t.pre);
    t.keep_mlp = pass.keep_mask(L.n, rate);
    point.feat = pass.residual(t.x2, pass.linear(t.f1, p + ".mlp.0.fc2"), t.keep_mlp);
    point.conv_feat = {};
}

void Block::backward(TrainingPass& pass, Ptv3Point& grad) const {
    const std::string& p = name_;
    const Ptv3Weights& W = pass.weights;
    const Ptv3Level& L = grad.at();
    const Tape t = take_last(pass.tape.blocks);
    const Tensor dy = grad.feat;
    Tensor d = pass.linear_backward(t.f1, p + ".mlp.0.fc2", pass.through_keep(dy, t.keep_mlp));
    pass.cmd.begin_pass("elementwise");
    d = grad::gelu_backward(pass.cmd, pass.pool, t.pre, d);
    d = pass.linear_backward(t.n2, p + ".mlp.0.fc1", d);
    Tensor dx2 = ops::add(pass.cmd, pass.pool, dy, pass.layer_norm_backward(t.x2, p + ".norm2.0", d));
    d = pass.linear_backward(t.a, p + ".attn.proj", pass.through_keep(dx2, t.keep_attn));
    pass.cmd.begin_pass("attention bwd");
    d = grad::window_attention_backward(pass.cmd, pass.pool, t.qkv, L.order_for_block(index_), L.offsets, heads_,
                                        patch_, scale_, d);
    d = pass.linear_backward(t.n1, p + ".attn.qkv", d, qkv_bias_);
    Tensor dx1 = ops::add(pass.cmd, pass.pool, dx2, pass.layer_norm_backward(t.x1, p + ".norm1.0", d));
    d = pass.layer_norm_backward(t.h2, p + ".cpe.2", dx1);
    d = pass.linear_backward(t.h1, p + ".cpe.1", d);
    pass.cmd.begin_pass("conv bwd");
    grad::ConvGrads g = grad::sparse_conv_backward(pass.cmd, pass.pool, t.cpe_in, L.rules3, cpe_weight(W), d);
    pass.grads[p + ".cpe.0.weight"] = reshaped(g.dw, W[p + ".cpe.0.weight"].shape);
    pass.grads[p + ".cpe.0.bias"] = g.db;
    if (t.separate_cpe_input) {
        grad.feat = dx1;
        grad.conv_feat = g.dx;
    } else {
        grad.feat = ops::add(pass.cmd, pass.pool, dx1, g.dx);
    }
}

}  // namespace pg::nn

#include "nn/train/trainer.h"

#include <cmath>
#include <numeric>
#include <stdexcept>

#include "nn/ops/attention.h"
#include "nn/ops/elementwise.h"
#include "nn/ops/linear.h"
#include "nn/ops/norm.h"
#include "nn/ops/pooling.h"
#include "nn/ops/sparse_conv.h"
#include "nn/ptv3/structure.h"
#include "nn/train/drop_path.h"
#include "nn/train/grad_attention.h"
#include "nn/train/grad_ops.h"

namespace pg::nn::train {
namespace {

constexpr float kBatchNormEps = 1e-3f;
constexpr float kLayerNormEps = 1e-5f;

// torch.linspace(0, rate, count) as Pointcept spaces drop path rates over blocks.
std::vector<double> linspace(double rate, int count) {
    std::vector<double> v(size_t(std::max(count, 0)));
    for (int i = 0; i < count; ++i) v[size_t(i)] = count > 1 ? rate * i / (count - 1) : 0.0;
    return v;
}

// What a transformer block's backward needs from its forward.
struct BlockTape {
    std::string p;
    const Ptv3Level* level = nullptr;
    int index = 0, heads = 1, patch = 1;
    float scale = 1;
    bool separate_cpe_input = false;
    Tensor cpe_in, h1, h2, x1, n1, qkv, a, x2, n2, pre, f1;
    Tensor keep_attn, keep_mlp;  // drop path row scales (undefined: no drop path)
};

// A BatchNorm (training mode) followed by GELU: the pooling, unpooling and embedding tail.
struct NormGeluTape {
    std::string p;
    Tensor x, mean, var, y;
};

struct DownTape {
    Tensor x;  // the finer level's output (the Linear's input)
    Tensor lin;
    NormGeluTape norm;
};

struct UpTape {
    Tensor deeper, lin_up, skip_in, lin_skip;
    NormGeluTape norm_up, norm_skip;
};

class Step {
public:
    Step(Pool& pool, const Ptv3Weights& w, double bn_momentum, std::mt19937_64& rng, vk::CommandList& cmd)
        : pool_(pool), W(w), c(w.config()), momentum_(bn_momentum), rng_(rng), cmd_(cmd) {}

    std::map<std::string, Tensor> grads;

    Tensor linear(const Tensor& x, const std::string& p, bool bias = true) {
        cmd_.begin_pass("linear");
        return ops::linear(cmd_, pool_, x, W[p + ".weight"], bias ? W[p + ".bias"] : Tensor{});
    }
    Tensor linear_back(const Tensor& x, const std::string& p, const Tensor& dy, bool bias = true) {
        cmd_.begin_pass("linear bwd");
        grad::LinearGrads g = grad::linear_backward(cmd_, pool_, x, W[p + ".weight"], dy);
        grads[p + ".weight"] = g.dw;
        if (bias) grads[p + ".bias"] = g.db;
        return g.dx;
    }
    Tensor layer_norm(const Tensor& x, const std::string& p, const Tensor& residual = {}) {
        cmd_.begin_pass("norm");
        return ops::layer_norm(cmd_, pool_, x, W[p + ".weight"], W[p + ".bias"], kLayerNormEps, residual);
    }
    Tensor layer_norm_back(const Tensor& x, const std::string& p, const Tensor& dy) {
        cmd_.begin_pass("norm bwd");
        grad::NormGrads g = grad::layer_norm_backward(cmd_, pool_, x, W[p + ".weight"], dy, kLayerNormEps);
        grads[p + ".weight"] = g.dgamma;
        grads[p + ".bias"] = g.dbeta;
        return g.dx;
    }
    Tensor norm_gelu(NormGeluTape& t, const std::string& p, const Tensor& x) {
        if (x.dim(0) < 2)
            throw std::invalid_argument("PTv3 training: BatchNorm '" + p + "' sees " + std::to_string(x.dim(0)) +
                                        " row(s); a batch needs at least 2 voxels at every level");
        cmd_.begin_pass("norm");
        grad::BatchNormTrain bn = grad::batch_norm_train(cmd_, pool_, x, W[p + ".weight"], W[p + ".bias"],
                                                         W[p + ".running_mean"], W[p + ".running_var"], kBatchNormEps,
                                                         float(momentum_));
        t = {p, x, bn.mean, bn.var, bn.y};
        return ops::gelu(cmd_, pool_, bn.y);
    }
    Tensor norm_gelu_back(const NormGeluTape& t, const Tensor& dy) {
        cmd_.begin_pass("norm bwd");
        Tensor d = grad::gelu_backward(cmd_, pool_, t.y, dy);
        grad::NormGrads g = grad::batch_norm_backward(cmd_, pool_, t.x, t.mean, t.var, W[t.p + ".weight"], d,
                                                      kBatchNormEps);
        grads[t.p + ".weight"] = g.dgamma;
        grads[t.p + ".bias"] = g.dbeta;
        return g.dx;
    }
    Tensor keep_mask(int64_t rows, double rate) {
        return rate > 0 ? drop_path_mask(cmd_, pool_, rows, rate, rng_) : Tensor{};
    }
    // x + branch, the branch's rows scaled by the drop path mask when there is one.
    Tensor residual(const Tensor& x, const Tensor& branch, const Tensor& keep) {
        cmd_.begin_pass("elementwise");
        return ops::add(cmd_, pool_, x, keep.defined() ? scale_rows(cmd_, pool_, branch, keep) : branch);
    }
    Tensor through_keep(const Tensor& dy, const Tensor& keep) {
        return keep.defined() ? scale_rows(cmd_, pool_, dy, keep) : dy;
    }

    Tensor block(BlockTape& t, Tensor x, const Ptv3Level& L, int C, int heads, int patch, int index,
                 const Tensor* cpe_input, double drop_rate) {
        const std::string& p = t.p;
        t.level = &L;
        t.index = index;
        t.heads = heads;
        t.patch = patch;
        t.scale = c.qk_scale > 0 ? float(c.qk_scale) : 1.0f / std::sqrt(float(C / heads));
        t.separate_cpe_input = cpe_input != nullptr;
        t.cpe_in = cpe_input ? *cpe_input : x;
        cmd_.begin_pass("conv");
        t.h1 = ops::sparse_conv(cmd_, pool_, t.cpe_in, L.rules3, reshaped(W[p + ".cpe.0.weight"], {C, 27 * C}),
                                W[p + ".cpe.0.bias"]);
        t.h2 = linear(t.h1, p + ".cpe.1");
        t.x1 = layer_norm(t.h2, p + ".cpe.2", x);
        t.n1 = layer_norm(t.x1, p + ".norm1.0");
        t.qkv = linear(t.n1, p + ".attn.qkv", c.qkv_bias);
        cmd_.begin_pass("attention");
        t.a = ops::window_attention(cmd_, pool_, t.qkv, L.order_for_block(index), L.offsets, heads, patch, t.scale);
        t.keep_attn = keep_mask(L.n, drop_rate);
        t.x2 = residual(t.x1, linear(t.a, p + ".attn.proj"), t.keep_attn);
        t.n2 = layer_norm(t.x2, p + ".norm2.0");
        t.pre = linear(t.n2, p + ".mlp.0.fc1");
        cmd_.begin_pass("elementwise");
        t.f1 = ops::gelu(cmd_, pool_, t.pre);
        t.keep_mlp = keep_mask(L.n, drop_rate);
        return residual(t.x2, linear(t.f1, p + ".mlp.0.fc2"), t.keep_mlp);
    }

    // Returns the gradient of the block's input x; a separate CPE input's gradient goes to *d_cpe_input.
    Tensor block_back(const BlockTape& t, const Tensor& dy, Tensor* d_cpe_input) {
        const std::string& p = t.p;
        const int C = int(t.x1.dim(1));
        Tensor d = linear_back(t.f1, p + ".mlp.0.fc2", through_keep(dy, t.keep_mlp));
        cmd_.begin_pass("elementwise");
        d = grad::gelu_backward(cmd_, pool_, t.pre, d);
        d = linear_back(t.n2, p + ".mlp.0.fc1", d);
        Tensor dx2 = ops::add(cmd_, pool_, dy, layer_norm_back(t.x2, p + ".norm2.0", d));
        d = linear_back(t.a, p + ".attn.proj", through_keep(dx2, t.keep_attn));
        cmd_.begin_pass("attention bwd");
        d = grad::window_attention_backward(cmd_, pool_, t.qkv, t.level->order_for_block(t.index), t.level->offsets,
                                            t.heads, t.patch, t.scale, d);
        d = linear_back(t.n1, p + ".attn.qkv", d, c.qkv_bias);
        Tensor dx1 = ops::add(cmd_, pool_, dx2, layer_norm_back(t.x1, p + ".norm1.0", d));
        d = layer_norm_back(t.h2, p + ".cpe.2", dx1);
        d = linear_back(t.h1, p + ".cpe.1", d);
        cmd_.begin_pass("conv bwd");
        grad::ConvGrads g = grad::sparse_conv_backward(cmd_, pool_, t.cpe_in, t.level->nbr3,
                                                       reshaped(W[p + ".cpe.0.weight"], {C, 27 * C}), d);
        grads[p + ".cpe.0.weight"] = reshaped(g.dw, W[p + ".cpe.0.weight"].shape);
        grads[p + ".cpe.0.bias"] = g.db;
        if (t.separate_cpe_input) {
            *d_cpe_input = g.dx;
            return dx1;
        }
        return ops::add(cmd_, pool_, dx1, g.dx);
    }

    Pool& pool_;
    const Ptv3Weights& W;
    const Ptv3Config& c;
    double momentum_;
    std::mt19937_64& rng_;
    vk::CommandList& cmd_;
};

}  // namespace

Trainer::Trainer(Pool& pool, Ptv3Weights weights, TrainOptions options)
    : pool_(pool), weights_(std::move(weights)), options_(options), adam_(pool, options.adamw), rng_(options.seed) {
    for (const auto& [name, shape] : Ptv3Weights::expected(config()))
        if (name.find("running_") == std::string::npos && name.find("num_batches_tracked") == std::string::npos)
            names_.push_back(name);
}

StepResult Trainer::gradients(const Ptv3Input& in, const std::vector<int32_t>& labels) {
    return run(in, labels, Mode::Gradients, 0, 0, options_.bn_momentum, options_.drop_path);
}

StepResult Trainer::step(const Ptv3Input& in, const std::vector<int32_t>& labels, double lr, double beta1) {
    return run(in, labels, Mode::Step, lr, beta1, options_.bn_momentum, options_.drop_path);
}

void Trainer::calibrate_batch_norm(const std::vector<Ptv3Input>& inputs) {
    // Momentum 1/(k+1) at batch k: a running mean of the batch statistics, the first replacing
    // whatever was there.
    for (size_t k = 0; k < inputs.size(); ++k)
        run(inputs[k], std::vector<int32_t>(inputs[k].size(), options_.ignore_label), Mode::Statistics, 0, 0,
            1.0 / double(k + 1), 0.0);
}

StepResult Trainer::run(const Ptv3Input& in, const std::vector<int32_t>& labels, Mode mode, double lr, double beta1,
                        double bn_momentum, double drop_path) {
    const Ptv3Config& c = config();
    Ptv3::validate(c, in);
    const int64_t n = int64_t(in.size());
    if (labels.size() != size_t(n))
        throw std::invalid_argument("PTv3 training: " + std::to_string(labels.size()) + " labels for " +
                                    std::to_string(n) + " points");
    vk::Context& ctx = pool_.context();
    vk::CommandList cmd(ctx);
    std::vector<vk::PassTiming> passes;

    Tensor feat_t = upload_tensor(pool_, in.feat, {n, c.in_channels}, DType::F32);
    Tensor labels_t = upload_tensor(pool_, labels, {n}, DType::I32);
    Ptv3Structure st = build_structure(cmd, pool_, c, in, passes);
    const std::vector<Ptv3Level>& levels = st.levels;
    Step S(pool_, weights_, bn_momentum, rng_, cmd);
    const auto& W = weights_;

    // Drop path rates per block, as Pointcept assigns them.
    int enc_blocks = 0, dec_blocks = 0;
    for (int d : c.enc_depths) enc_blocks += d;
    for (int d : c.dec_depths) dec_blocks += d;
    const std::vector<double> enc_rate = linspace(drop_path, enc_blocks);
    const std::vector<double> dec_rate = linspace(drop_path, dec_blocks);

    // Forward, keeping the tapes.
    cmd.begin_pass("conv");
    Tensor x0 = ops::gather_rows(cmd, pool_, feat_t, st.vox.first);
    const Tensor stem_w = reshaped(W["embedding.stem.conv.weight"], {c.enc_channels[0], 125 * c.in_channels});
    Tensor stem = ops::sparse_conv(cmd, pool_, x0, st.nbr5, stem_w, Tensor{});
    NormGeluTape stem_tape;
    Tensor x = S.norm_gelu(stem_tape, "embedding.stem.norm", stem);

    const int stages = c.stages();
    const size_t levels_n = levels.size();
    std::vector<std::vector<BlockTape>> enc_tapes(levels_n), dec_tapes(levels_n);
    std::vector<DownTape> downs(levels_n);
    std::vector<UpTape> ups(levels_n);
    std::vector<Tensor> skips(levels_n);
    for (int s = 0, b = 0; s < stages; ++s) {
        const std::string p = "enc.enc" + std::to_string(s);
        const Ptv3Level& L = levels[size_t(s)];
        if (s > 0) {
            DownTape& d = downs[size_t(s)];
            d.x = x;
            d.lin = S.linear(x, p + ".down.proj");
            cmd.begin_pass("pool");
            x = S.norm_gelu(d.norm, p + ".down.norm.0", ops::segment_max(cmd, pool_, d.lin, L.clusters));
        }
        auto& tapes = enc_tapes[size_t(s)];
        tapes.resize(size_t(c.enc_depths[size_t(s)]));
        for (int i = 0; i < c.enc_depths[size_t(s)]; ++i, ++b) {
            tapes[size_t(i)].p = p + ".block" + std::to_string(i);
            x = S.block(tapes[size_t(i)], x, L, c.enc_channels[size_t(s)], c.enc_num_head[size_t(s)],
                        c.enc_patch_size[size_t(s)], i, nullptr, enc_rate[size_t(b)]);
        }
        skips[size_t(s)] = x;
    }
    for (int s = stages - 2; s >= 0; --s) {
        const std::string p = "dec.dec" + std::to_string(s);
        const Ptv3Level& L = levels[size_t(s)];
        UpTape& u = ups[size_t(s)];
        u.deeper = x;
        u.lin_up = S.linear(x, p + ".up.proj.0");
        Tensor up = S.norm_gelu(u.norm_up, p + ".up.proj.1", u.lin_up);
        u.skip_in = skips[size_t(s)];
        u.lin_skip = S.linear(u.skip_in, p + ".up.proj_skip.0");
        Tensor skip = S.norm_gelu(u.norm_skip, p + ".up.proj_skip.1", u.lin_skip);
        cmd.begin_pass("elementwise");
        x = ops::add_gathered(cmd, pool_, skip, up, levels[size_t(s + 1)].clusters.cluster);
        auto& tapes = dec_tapes[size_t(s)];
        const int depth = c.dec_depths[size_t(s)];
        tapes.resize(size_t(depth));
        // Pointcept reverses each decoder stage's slice of the rates.
        int first = 0;
        for (int k = 0; k < s; ++k) first += c.dec_depths[size_t(k)];
        for (int i = 0; i < depth; ++i) {
            tapes[size_t(i)].p = p + ".block" + std::to_string(i);
            // The release's first decoder block convolves the skip projection alone (see model.cpp).
            x = S.block(tapes[size_t(i)], x, L, c.dec_channels[size_t(s)], c.dec_num_head[size_t(s)],
                        c.dec_patch_size[size_t(s)], i, i == 0 ? &skip : nullptr,
                        dec_rate[size_t(first + depth - 1 - i)]);
        }
    }
    const Tensor head_in = x;
    Tensor logits = S.linear(x, "head");
    cmd.begin_pass("loss");
    Tensor voxel_labels = ops::gather_rows(cmd, pool_, labels_t, st.vox.first);
    grad::CrossEntropy ce = grad::cross_entropy(cmd, pool_, logits, voxel_labels, options_.ignore_label);
    Tensor dlogits = ce.dlogits, lovasz_loss;
    if (options_.lovasz_weight > 0 && mode != Mode::Statistics) {  // statistics passes need no loss
        grad::Lovasz lv = grad::lovasz_softmax(cmd, pool_, logits, voxel_labels, options_.ignore_label,
                                               float(options_.lovasz_weight));
        dlogits = ops::add(cmd, pool_, ce.dlogits, lv.dlogits);
        lovasz_loss = lv.loss;
    }
    Tensor point_logits = ops::gather_rows(cmd, pool_, logits, st.vox.inverse);

    if (mode == Mode::Statistics) {
        cmd.submit_and_wait();
        return {};
    }

    // Backward.
    Tensor d = S.linear_back(head_in, "head", dlogits);
    std::vector<Tensor> d_skips(levels_n);
    for (int s = 0; s < stages - 1; ++s) {
        const std::string p = "dec.dec" + std::to_string(s);
        auto& tapes = dec_tapes[size_t(s)];
        Tensor d_skip;
        for (int i = int(tapes.size()) - 1; i >= 0; --i) d = S.block_back(tapes[size_t(i)], d, &d_skip);
        const UpTape& u = ups[size_t(s)];
        // x = skip + up[cluster]: skip gets d (plus the first block's CPE branch), up the cluster sums.
        cmd.begin_pass("elementwise");
        d_skip = d_skip.defined() ? ops::add(cmd, pool_, d, d_skip) : d;
        grad::AddGatheredGrads ag =
            grad::add_gathered_backward(cmd, pool_, d, grad::group_rows(levels[size_t(s + 1)].clusters));
        Tensor dl = S.norm_gelu_back(u.norm_skip, d_skip);
        d_skips[size_t(s)] = S.linear_back(u.skip_in, p + ".up.proj_skip.0", dl);
        dl = S.norm_gelu_back(u.norm_up, ag.dx);
        d = S.linear_back(u.deeper, p + ".up.proj.0", dl);
    }
    for (int s = stages - 1; s >= 0; --s) {
        if (d_skips[size_t(s)].defined()) d = ops::add(cmd, pool_, d, d_skips[size_t(s)]);
        auto& tapes = enc_tapes[size_t(s)];
        for (int i = int(tapes.size()) - 1; i >= 0; --i) d = S.block_back(tapes[size_t(i)], d, nullptr);
        if (s > 0) {
            const std::string p = "enc.enc" + std::to_string(s);
            const DownTape& dt = downs[size_t(s)];
            Tensor dm = S.norm_gelu_back(dt.norm, d);
            cmd.begin_pass("pool bwd");
            Tensor dl = grad::segment_max_backward(cmd, pool_, dt.lin, levels[size_t(s)].clusters, dm);
            d = S.linear_back(dt.x, p + ".down.proj", dl);
        }
    }
    Tensor dstem = S.norm_gelu_back(stem_tape, d);
    cmd.begin_pass("conv bwd");
    grad::ConvGrads stem_g = grad::sparse_conv_backward(cmd, pool_, x0, st.nbr5, stem_w, dstem);
    S.grads["embedding.stem.conv.weight"] = reshaped(stem_g.dw, W["embedding.stem.conv.weight"].shape);

    if (mode == Mode::Step) {
        cmd.begin_pass("optimizer");
        std::vector<Tensor> params, grads;
        for (const std::string& name : names_) {
            params.push_back(W[name]);
            grads.push_back(S.grads.at(name));
        }
        adam_.step(cmd, params, grads, lr, beta1);
    }
    cmd.submit_and_wait();

    StepResult r;
    r.passes = std::move(passes);
    for (const auto& p : cmd.timings()) r.passes.push_back(p);
    r.voxels = st.vox.count;
    r.loss = download_tensor<float>(ctx, ce.loss)[0];
    if (lovasz_loss.defined()) {
        r.lovasz = download_tensor<float>(ctx, lovasz_loss)[0];
        r.loss += r.lovasz;
    }
    r.counted = int64_t(download_tensor<uint32_t>(ctx, ce.info)[0]);
    r.logits = download_tensor<float>(ctx, point_logits);
    r.logits.resize(size_t(n * c.num_classes));
    r.grads = std::move(S.grads);
    return r;
}

}  // namespace pg::nn::train

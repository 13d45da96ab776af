#include "nn/ptv3/model.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>

#include "nn/ops/attention.h"
#include "nn/ops/elementwise.h"
#include "nn/ops/linear.h"
#include "nn/ops/neighbors.h"
#include "nn/ops/norm.h"
#include "nn/ops/pooling.h"
#include "nn/ops/serialize.h"
#include "nn/ops/sparse_conv.h"
#include "nn/ops/voxelize.h"
#include "nn/ptv3/structure.h"

namespace pg::nn {
namespace {

constexpr float kBatchNormEps = 1e-3f;
constexpr float kLayerNormEps = 1e-5f;

}  // namespace

std::vector<int32_t> Ptv3::grid_coords(const std::vector<float>& coord, double grid_size) {
    const size_t n = coord.size() / 3;
    float lo[3] = {INFINITY, INFINITY, INFINITY};
    for (size_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], coord[3 * i + a]);
    const float g = float(grid_size);
    std::vector<int32_t> grid(3 * n);
    for (size_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) {
            float d = coord[3 * i + a] - lo[a];  // float32 steps, as torch does them (x86-64: no excess precision)
            float q = d / g;
            grid[3 * i + a] = int32_t(std::trunc(q));
        }
    return grid;
}

void Ptv3::validate(const Ptv3Config& c, const Ptv3Input& in) {
    const int64_t n = int64_t(in.size());
    if (n == 0 || in.coord.size() != size_t(3 * n)) throw std::invalid_argument("PTv3 input: coord must be [n, 3], n > 0");
    if (in.feat.size() != size_t(n * c.in_channels))
        throw std::invalid_argument("PTv3 input: feat must be [n, " + std::to_string(c.in_channels) + "]");
    for (float v : in.coord)
        if (!std::isfinite(v)) throw std::invalid_argument("PTv3 input: coordinates must be finite");
    const std::vector<int64_t> ends = in.offsets.empty() ? std::vector<int64_t>{n} : in.offsets;
    for (size_t b = 0; b < ends.size(); ++b)
        if (ends[b] <= (b ? ends[b - 1] : 0) || ends[b] > n)
            throw std::invalid_argument("PTv3 input: offsets must increase strictly (no empty cloud)");
    if (ends.back() != n) throw std::invalid_argument("PTv3 input: the last offset must equal the point count");
    const size_t kinds = c.order.size();
    if (!in.perms.empty() && in.perms.size() != size_t(c.stages()))
        throw std::invalid_argument("PTv3 input: one order permutation per level (" + std::to_string(c.stages()) +
                                    ") is needed");
    for (const auto& p : in.perms) {
        std::vector<int> s = p;
        std::sort(s.begin(), s.end());
        bool ok = s.size() == kinds;
        for (size_t k = 0; ok && k < s.size(); ++k) ok = s[k] == int(k);
        if (!ok) throw std::invalid_argument("PTv3 input: each permutation must reorder 0.." + std::to_string(kinds - 1));
    }
}

std::vector<int32_t> Ptv3::voxel_points() const {
    if (!voxel_points_.defined()) return {};
    return download_tensor<int32_t>(pool_.context(), voxel_points_);
}

Ptv3::Ptv3(Pool& pool, Ptv3Weights weights) : pool_(pool), weights_(std::move(weights)) {}

Ptv3Output Ptv3::forward(const Ptv3Input& in, const Ptv3Trace& trace) {
    const Ptv3Config& c = config();
    const Ptv3Weights& W = weights_;
    const int64_t n = int64_t(in.size());
    validate(c, in);

    vk::Context& ctx = pool_.context();
    vk::CommandList cmd(ctx);
    Ptv3Output out;
    auto collect = [&] {
        for (const auto& p : cmd.timings()) out.passes.push_back(p);
    };
    auto sync = [&] {
        cmd.submit_and_wait();
        collect();
    };
    struct ConvUse {
        Tensor nbr;
        int64_t cin, cout;
    };
    std::vector<ConvUse> convs;
    auto linear = [&](const Tensor& a, const Tensor& w, const Tensor& b, const Tensor& residual = {},
                      ops::Activation act = ops::Activation::None) {
        out.flops["linear"] += 2.0 * double(a.dim(0)) * double(w.dim(0)) * double(w.dim(1));
        return ops::linear(cmd, pool_, a, w, b, residual, act);
    };
    // `rules`: nbr's rulebook where the level keeps one; without, sparse_conv builds one if it uses it.
    auto conv = [&](const Tensor& a, const Tensor& nbr, const Tensor& w, const Tensor& b,
                    const ops::Rulebook* rules = nullptr) {
        convs.push_back({nbr, a.dim(1), w.dim(0)});
        return rules ? ops::sparse_conv(cmd, pool_, a, *rules, w, b) : ops::sparse_conv(cmd, pool_, a, nbr, w, b);
    };
    auto emit = [&](const std::string& name, const Tensor& t) {
        if (!trace) return;
        sync();
        trace(name, t);
    };

    // Uploaded before any recording: a host write into a pooled buffer must not race the stream.
    Tensor feat_t = upload_tensor(pool_, in.feat, {n, c.in_channels}, DType::F32);
    Ptv3Structure st = build_structure(cmd, pool_, c, in, out.passes);
    const ops::Voxels& vox = st.vox;
    const std::vector<Ptv3Level>& levels = st.levels;
    voxel_points_ = vox.first;
    out.voxels = vox.count;

    auto block = [&](const std::string& p, Tensor x, const Ptv3Level& L, int C, int heads, int patch, int index,
                     const Tensor* cpe_input) {
        const float scale = c.qk_scale > 0 ? float(c.qk_scale) : 1.0f / std::sqrt(float(C / heads));
        cmd.begin_pass("conv");
        Tensor h = conv(cpe_input ? *cpe_input : x, L.nbr3,
                                    reshaped(W[p + ".cpe.0.weight"], {C, 27 * C}), W[p + ".cpe.0.bias"], &L.rules3);
        emit(p + ".cpe.0/feat", h);
        cmd.begin_pass("linear");
        h = linear(h, W[p + ".cpe.1.weight"], W[p + ".cpe.1.bias"]);
        emit(p + ".cpe.1/feat", h);
        cmd.begin_pass("norm");
        if (trace) {
            h = ops::layer_norm(cmd, pool_, h, W[p + ".cpe.2.weight"], W[p + ".cpe.2.bias"], kLayerNormEps);
            emit(p + ".cpe.2/feat", h);
            emit(p + ".cpe/feat", h);
            x = ops::add(cmd, pool_, x, h);
        } else {
            x = ops::layer_norm(cmd, pool_, h, W[p + ".cpe.2.weight"], W[p + ".cpe.2.bias"], kLayerNormEps, x);
        }
        cmd.begin_pass("norm");
        h = ops::layer_norm(cmd, pool_, x, W[p + ".norm1.0.weight"], W[p + ".norm1.0.bias"], kLayerNormEps);
        emit(p + ".norm1/feat", h);
        cmd.begin_pass("linear");
        Tensor qkv = linear(h, W[p + ".attn.qkv.weight"],
                                 c.qkv_bias ? W[p + ".attn.qkv.bias"] : Tensor{});
        cmd.begin_pass("attention");
        for (size_t b = 0; b + 1 < L.offsets_host.size(); ++b) {
            const double nb = L.offsets_host[b + 1] - L.offsets_host[b];
            out.flops["attention"] += 4.0 * C * nb * std::min<double>(nb, patch);
        }
        h = ops::window_attention(cmd, pool_, qkv, L.order_for_block(index), L.offsets, heads, patch, scale);
        cmd.begin_pass("linear");
        if (trace) {
            h = linear(h, W[p + ".attn.proj.weight"], W[p + ".attn.proj.bias"]);
            emit(p + ".attn/feat", h);
            x = ops::add(cmd, pool_, x, h);
        } else {
            x = linear(h, W[p + ".attn.proj.weight"], W[p + ".attn.proj.bias"], x);
        }
        cmd.begin_pass("norm");
        h = ops::layer_norm(cmd, pool_, x, W[p + ".norm2.0.weight"], W[p + ".norm2.0.bias"], kLayerNormEps);
        emit(p + ".norm2/feat", h);
        cmd.begin_pass("linear");
        h = linear(h, W[p + ".mlp.0.fc1.weight"], W[p + ".mlp.0.fc1.bias"], Tensor{}, ops::Activation::Gelu);
        if (trace) {
            h = linear(h, W[p + ".mlp.0.fc2.weight"], W[p + ".mlp.0.fc2.bias"]);
            emit(p + ".mlp/feat", h);
            x = ops::add(cmd, pool_, x, h);
        } else {
            x = linear(h, W[p + ".mlp.0.fc2.weight"], W[p + ".mlp.0.fc2.bias"], x);
        }
        emit(p + "/feat", x);
        return x;
    };
    auto bn = [&](const Tensor& x, const std::string& p, bool gelu) {
        cmd.begin_pass("norm");
        return ops::batch_norm(cmd, pool_, x, W[p + ".running_mean"], W[p + ".running_var"], W[p + ".weight"],
                               W[p + ".bias"], kBatchNormEps, gelu);
    };

    // Embedding.
    cmd.begin_pass("elementwise");
    Tensor x = ops::gather_rows(cmd, pool_, feat_t, vox.first);
    cmd.begin_pass("conv");
    x = conv(x, st.nbr5,
                         reshaped(W["embedding.stem.conv.weight"], {c.enc_channels[0], 125 * c.in_channels}), Tensor{});
    emit("embedding.stem.conv/feat", x);
    x = bn(x, "embedding.stem.norm", true);
    emit("embedding/feat", x);

    // Encoder.
    std::vector<Tensor> skips(size_t(c.stages()));
    for (int s = 0; s < c.stages(); ++s) {
        const std::string p = "enc.enc" + std::to_string(s);
        const Ptv3Level& L = levels[size_t(s)];
        if (s > 0) {
            cmd.begin_pass("linear");
            x = linear(x, W[p + ".down.proj.weight"], W[p + ".down.proj.bias"]);
            cmd.begin_pass("pool");
            x = ops::segment_max(cmd, pool_, x, L.clusters);
            x = bn(x, p + ".down.norm.0", true);
            emit(p + ".down/feat", x);
        }
        for (int i = 0; i < c.enc_depths[size_t(s)]; ++i)
            x = block(p + ".block" + std::to_string(i), x, L, c.enc_channels[size_t(s)], c.enc_num_head[size_t(s)],
                      c.enc_patch_size[size_t(s)], i, nullptr);
        emit(p + "/feat", x);
        skips[size_t(s)] = x;
        out.level_points.push_back(L.n);
    }

    // Decoder.
    for (int s = c.stages() - 2; s >= 0; --s) {
        const std::string p = "dec.dec" + std::to_string(s);
        const Ptv3Level& L = levels[size_t(s)];
        cmd.begin_pass("linear");
        Tensor up = linear(x, W[p + ".up.proj.0.weight"], W[p + ".up.proj.0.bias"]);
        up = bn(up, p + ".up.proj.1", true);
        cmd.begin_pass("linear");
        Tensor skip = linear(skips[size_t(s)], W[p + ".up.proj_skip.0.weight"],
                                  W[p + ".up.proj_skip.0.bias"]);
        skip = bn(skip, p + ".up.proj_skip.1", true);
        cmd.begin_pass("elementwise");
        x = ops::add_gathered(cmd, pool_, skip, up, levels[size_t(s + 1)].clusters.cluster);
        emit(p + ".up/feat", x);
        skips[size_t(s + 1)] = {};
        for (int i = 0; i < c.dec_depths[size_t(s)]; ++i)
            // The release's first decoder block convolves the skip projection alone (its
            // sparse tensor was not updated by the unpooling sum); trained weights expect it.
            x = block(p + ".block" + std::to_string(i), x, L, c.dec_channels[size_t(s)], c.dec_num_head[size_t(s)],
                      c.dec_patch_size[size_t(s)], i, i == 0 ? &skip : nullptr);
        emit(p + "/feat", x);
    }

    cmd.begin_pass("linear");
    Tensor logits = linear(x, W["head.weight"], W["head.bias"]);
    emit("logits/voxels", logits);
    cmd.begin_pass("elementwise");
    logits = ops::gather_rows(cmd, pool_, logits, vox.inverse);
    sync();
    out.logits = download_tensor<float>(ctx, logits);
    if (in.count_conv_pairs)
        for (const auto& u : convs) {
            double pairs = 0;
            for (int32_t v : download_tensor<int32_t>(ctx, u.nbr)) pairs += v >= 0;
            out.flops["sparse_conv"] += 2.0 * pairs * double(u.cin) * double(u.cout);
        }
    out.logits.resize(size_t(n * c.num_classes));
    return out;
}

}  // namespace pg::nn

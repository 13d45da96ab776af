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

namespace pg::nn {
namespace {

constexpr float kBatchNormEps = 1e-3f;
constexpr float kLayerNormEps = 1e-5f;

ops::Order order_kind(const std::string& name) {
    if (name == "z") return ops::Order::Z;
    if (name == "z-trans") return ops::Order::ZTrans;
    if (name == "hilbert") return ops::Order::Hilbert;
    return ops::Order::HilbertTrans;
}

int bit_length(uint64_t v) { return v ? 64 - std::countl_zero(v) : 0; }

// A tensor viewed with another shape (same buffer), e.g. conv weights [O,k,k,k,I] as [O, k^3 I].
Tensor reshaped(const Tensor& t, std::vector<int64_t> shape) {
    Tensor r = t;
    r.shape = std::move(shape);
    return r;
}

// One resolution of the U-Net: its voxels, serialization and neighbourhoods.
struct Level {
    int64_t n = 0;
    int depth = 0;
    Tensor grid, batch;
    std::vector<int32_t> batch_host;
    std::vector<Tensor> codes;        // per order kind (config.order index)
    std::vector<ops::Sorted> sorted;  // per order kind
    std::vector<int> rows;            // row j of the release's code tensor holds kind rows[j]
    Tensor nbr3;
    ops::Rulebook rules3;             // nbr3's, built once for all the level's convolutions
    Tensor offsets;                   // attention: cloud boundaries in serialized positions
    std::vector<int32_t> offsets_host;
    ops::Clusters clusters;           // from the finer level (levels > 0)
};

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
    const size_t kinds = c.order.size();
    std::vector<int64_t> ends = in.offsets.empty() ? std::vector<int64_t>{n} : in.offsets;

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

    // Host: grid and cloud ids, as the release computes them.
    const std::vector<int32_t> grid = grid_coords(in.coord, c.grid_size);
    std::vector<int32_t> batch(static_cast<size_t>(n));
    for (size_t b = 0, i = 0; b < ends.size(); ++b)
        for (; int64_t(i) < ends[b]; ++i) batch[i] = int32_t(b);
    const int clouds = int(ends.size());
    const int batch_bits = bit_length(uint64_t(clouds - 1));
    int32_t max_grid = 0;
    for (int32_t v : grid) max_grid = std::max(max_grid, v);
    if (3 * bit_length(uint64_t(max_grid)) + batch_bits > 63)
        throw std::invalid_argument("PTv3 input: the cloud spans too many voxels for 64-bit serialization codes");

    // Voxels: the network runs on one point per voxel.
    Tensor grid_t = upload_tensor(pool_, grid, {n, 3}, DType::I32);
    Tensor batch_t = upload_tensor(pool_, batch, {n}, DType::I32);
    Tensor feat_t = upload_tensor(pool_, in.feat, {n, c.in_channels}, DType::F32);
    cmd.begin_pass("voxelize");
    ops::Voxels vox = ops::voxelize(cmd, pool_, grid_t, batch_t);
    collect();
    voxel_points_ = vox.first;
    out.voxels = vox.count;

    auto make_offsets = [&](Level& L) {
        L.offsets_host.assign(size_t(clouds) + 1, 0);
        for (int32_t v : L.batch_host) L.offsets_host[size_t(v) + 1]++;
        for (int k = 0; k < clouds; ++k) L.offsets_host[size_t(k) + 1] += L.offsets_host[size_t(k)];
        // In the stream, not a host write: the pool may hand out a buffer that commands recorded
        // earlier in this stream still use.
        L.offsets = pool_.empty({clouds + 1}, DType::I32);
        cmd.update(*L.offsets.buffer, L.offsets_host.data(), L.offsets_host.size() * sizeof(int32_t));
    };
    auto sort_level = [&](Level& L) {
        cmd.begin_pass("serialize");
        const int key_bits = std::max(1, 3 * L.depth + batch_bits);
        L.sorted.clear();
        for (size_t k = 0; k < kinds; ++k) L.sorted.push_back(ops::sort_codes(cmd, pool_, L.codes[k], key_bits));
        cmd.begin_pass("neighbors");
        L.nbr3 = ops::neighbor_map(cmd, pool_, L.grid, L.batch, 3);
        L.rules3 = ops::build_rulebook(cmd, pool_, L.nbr3);
        make_offsets(L);
    };
    auto level_rows = [&](const std::vector<int>& parent_rows, int level) {
        std::vector<int> rows(kinds);
        for (size_t j = 0; j < kinds; ++j) {
            int src = in.perms.empty() ? int(j) : in.perms[size_t(level)][j];
            rows[j] = parent_rows.empty() ? src : parent_rows[size_t(src)];
        }
        return rows;
    };

    std::vector<Level> levels(size_t(c.stages()));
    {
        Level& L = levels[0];
        L.n = vox.count;
        L.grid = vox.grid;
        L.batch = vox.batch;
        L.batch_host = download_tensor<int32_t>(ctx, vox.batch);
        L.batch_host.resize(size_t(L.n));
        L.depth = bit_length(uint64_t(max_grid));
        L.rows = level_rows({}, 0);
        cmd.begin_pass("serialize");
        for (size_t k = 0; k < kinds; ++k)
            L.codes.push_back(ops::serialize_codes(cmd, pool_, L.grid, L.batch, order_kind(c.order[k]), L.depth));
        sort_level(L);
    }

    auto block = [&](const std::string& p, Tensor x, const Level& L, int C, int heads, int patch, int index,
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
        const int row = L.rows[size_t(index) % kinds];
        for (size_t b = 0; b + 1 < L.offsets_host.size(); ++b) {
            const double nb = L.offsets_host[b + 1] - L.offsets_host[b];
            out.flops["attention"] += 4.0 * C * nb * std::min<double>(nb, patch);
        }
        h = ops::window_attention(cmd, pool_, qkv, L.sorted[size_t(row)].order, L.offsets, heads, patch, scale);
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
    cmd.begin_pass("neighbors");
    Tensor nbr5 = ops::neighbor_map(cmd, pool_, levels[0].grid, levels[0].batch, 5);
    cmd.begin_pass("conv");
    x = conv(x, nbr5,
                         reshaped(W["embedding.stem.conv.weight"], {c.enc_channels[0], 125 * c.in_channels}), Tensor{});
    emit("embedding.stem.conv/feat", x);
    x = bn(x, "embedding.stem.norm", true);
    emit("embedding/feat", x);

    // Encoder.
    std::vector<Tensor> skips(size_t(c.stages()));
    for (int s = 0; s < c.stages(); ++s) {
        const std::string p = "enc.enc" + std::to_string(s);
        if (s > 0) {
            Level& P = levels[size_t(s - 1)];
            Level& L = levels[size_t(s)];
            const int shift = bit_length(uint64_t(c.stride[size_t(s - 1)] - 1));
            cmd.begin_pass("pool");
            L.clusters = ops::pool_clusters(cmd, pool_, P.codes[size_t(P.rows[0])], 3 * shift);
            collect();
            L.n = L.clusters.count;
            L.depth = P.depth - shift;
            std::vector<int32_t> head = download_tensor<int32_t>(ctx, L.clusters.head);
            L.batch_host.resize(size_t(L.n));
            for (int64_t m = 0; m < L.n; ++m) L.batch_host[size_t(m)] = P.batch_host[size_t(head[size_t(m)])];
            L.grid = ops::pool_grid(cmd, pool_, P.grid, L.clusters, shift);
            L.batch = ops::gather_batch(cmd, pool_, P.batch, L.clusters);
            for (size_t k = 0; k < kinds; ++k)
                L.codes.push_back(ops::pool_codes(cmd, pool_, P.codes[k], L.clusters, 3 * shift));
            L.rows = level_rows(P.rows, s);
            sort_level(L);
            cmd.begin_pass("linear");
            x = linear(x, W[p + ".down.proj.weight"], W[p + ".down.proj.bias"]);
            cmd.begin_pass("pool");
            x = ops::segment_max(cmd, pool_, x, L.clusters);
            x = bn(x, p + ".down.norm.0", true);
            emit(p + ".down/feat", x);
        }
        const Level& L = levels[size_t(s)];
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
        const Level& L = levels[size_t(s)];
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

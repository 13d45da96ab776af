#include "nn/ptv3/model.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>

#include "nn/ops/elementwise.h"
#include "nn/ptv3/inference_pass.h"
#include "nn/ptv3/point.h"
#include "nn/ptv3/structure.h"

namespace pg::nn {

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

Ptv3::Ptv3(Pool& pool, Ptv3Weights weights)
    : pool_(pool), weights_(std::move(weights)), network_(weights_.config()) {}

Ptv3Output Ptv3::forward(const Ptv3Input& in, const Ptv3Trace& trace) {
    const Ptv3Config& c = config();
    const int64_t n = int64_t(in.size());
    validate(c, in);

    vk::Context& ctx = pool_.context();
    vk::CommandList cmd(ctx);
    Ptv3Output out;
    // Uploaded before any recording: a host write into a pooled buffer must not race the stream.
    Tensor feat = upload_tensor(pool_, in.feat, {n, c.in_channels}, DType::F32);
    const Ptv3Structure st = build_structure(cmd, pool_, c, in, out.passes);
    voxel_points_ = st.vox.first;
    out.voxels = st.vox.count;
    for (const Ptv3Level& level : st.levels) out.level_points.push_back(level.n);

    InferencePass pass(cmd, pool_, weights_, trace, out);
    Ptv3Point point{&st, 0, std::move(feat)};
    network_.forward(pass, point);
    cmd.begin_pass("elementwise");
    const Tensor logits = ops::gather_rows(cmd, pool_, point.feat, st.vox.inverse);
    pass.sync();
    out.logits = download_tensor<float>(ctx, logits);
    if (in.count_conv_pairs) pass.count_conv_pairs();
    out.logits.resize(size_t(n * c.num_classes));
    return out;
}

}  // namespace pg::nn

#include "nn/ptv3/structure.h"

#include <algorithm>
#include <bit>
#include <stdexcept>

#include "nn/ops/neighbors.h"
#include "nn/ptv3/model.h"

namespace pg::nn {
namespace {

ops::Order order_kind(const std::string& name) {
    if (name == "z") return ops::Order::Z;
    if (name == "z-trans") return ops::Order::ZTrans;
    if (name == "hilbert") return ops::Order::Hilbert;
    return ops::Order::HilbertTrans;
}

int bit_length(uint64_t v) { return v ? 64 - std::countl_zero(v) : 0; }

}  // namespace

Ptv3Structure build_structure(vk::CommandList& cmd, Pool& pool, const Ptv3Config& c, const Ptv3Input& in,
                              std::vector<vk::PassTiming>& passes) {
    const int64_t n = int64_t(in.size());
    const size_t kinds = c.order.size();
    const std::vector<int64_t> ends = in.offsets.empty() ? std::vector<int64_t>{n} : in.offsets;
    vk::Context& ctx = pool.context();
    auto collect = [&] {
        for (const auto& p : cmd.timings()) passes.push_back(p);
    };

    // Host: grid and cloud ids, as the release computes them.
    const std::vector<int32_t> grid = Ptv3::grid_coords(in.coord, c.grid_size);
    std::vector<int32_t> batch(static_cast<size_t>(n));
    for (size_t b = 0, i = 0; b < ends.size(); ++b)
        for (; int64_t(i) < ends[b]; ++i) batch[i] = int32_t(b);
    Ptv3Structure st;
    st.clouds = int(ends.size());
    const int batch_bits = bit_length(uint64_t(st.clouds - 1));
    int32_t max_grid = 0;
    for (int32_t v : grid) max_grid = std::max(max_grid, v);
    if (3 * bit_length(uint64_t(max_grid)) + batch_bits > 63)
        throw std::invalid_argument("PTv3 input: the cloud spans too many voxels for 64-bit serialization codes");

    // Voxels: the network runs on one point per voxel.
    Tensor grid_t = upload_tensor(pool, grid, {n, 3}, DType::I32);
    Tensor batch_t = upload_tensor(pool, batch, {n}, DType::I32);
    cmd.begin_pass("voxelize");
    // Key bits of (batch, x, y, z) at a level's depth: the sorts pass over these digits only.
    auto grid_key_bits = [&](int depth) { return std::max(1, 3 * depth + batch_bits); };
    st.vox = ops::voxelize(cmd, pool, grid_t, batch_t, grid_key_bits(bit_length(uint64_t(max_grid))));
    collect();

    auto make_offsets = [&](Ptv3Level& L) {
        L.offsets_host.assign(size_t(st.clouds) + 1, 0);
        for (int32_t v : L.batch_host) L.offsets_host[size_t(v) + 1]++;
        for (int k = 0; k < st.clouds; ++k) L.offsets_host[size_t(k) + 1] += L.offsets_host[size_t(k)];
        // In the stream, not a host write: the pool may hand out a buffer that commands recorded
        // earlier in this stream still use.
        L.offsets = pool.empty({st.clouds + 1}, DType::I32);
        cmd.update(*L.offsets.buffer, L.offsets_host.data(), L.offsets_host.size() * sizeof(int32_t));
    };
    auto sort_level = [&](Ptv3Level& L) {
        cmd.begin_pass("serialize");
        const int key_bits = grid_key_bits(L.depth);  // codes hold the batch above 3 x depth bits too
        L.sorted.clear();
        for (size_t k = 0; k < kinds; ++k) L.sorted.push_back(ops::sort_codes(cmd, pool, L.codes[k], key_bits));
        cmd.begin_pass("neighbors");
        L.nbr3 = ops::neighbor_map(cmd, pool, L.grid, L.batch, 3, key_bits);
        L.rules3 = ops::build_rulebook(cmd, pool, L.nbr3);
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

    st.levels.resize(size_t(c.stages()));
    {
        Ptv3Level& L = st.levels[0];
        L.n = st.vox.count;
        L.grid = st.vox.grid;
        L.batch = st.vox.batch;
        L.batch_host = download_tensor<int32_t>(ctx, st.vox.batch);
        L.batch_host.resize(size_t(L.n));
        L.depth = bit_length(uint64_t(max_grid));
        L.rows = level_rows({}, 0);
        cmd.begin_pass("serialize");
        for (size_t k = 0; k < kinds; ++k)
            L.codes.push_back(ops::serialize_codes(cmd, pool, L.grid, L.batch, order_kind(c.order[k]), L.depth));
        sort_level(L);
        cmd.begin_pass("neighbors");
        st.nbr5 = ops::neighbor_map(cmd, pool, L.grid, L.batch, 5, grid_key_bits(L.depth));
    }
    for (int s = 1; s < c.stages(); ++s) {
        Ptv3Level& P = st.levels[size_t(s - 1)];
        Ptv3Level& L = st.levels[size_t(s)];
        const int shift = bit_length(uint64_t(c.stride[size_t(s - 1)] - 1));
        cmd.begin_pass("pool");
        L.clusters = ops::pool_clusters(cmd, pool, P.codes[size_t(P.rows[0])], 3 * shift, grid_key_bits(P.depth));
        collect();
        L.n = L.clusters.count;
        L.depth = P.depth - shift;
        const std::vector<int32_t> head = download_tensor<int32_t>(ctx, L.clusters.head);
        L.batch_host.resize(size_t(L.n));
        for (int64_t m = 0; m < L.n; ++m) L.batch_host[size_t(m)] = P.batch_host[size_t(head[size_t(m)])];
        L.grid = ops::pool_grid(cmd, pool, P.grid, L.clusters, shift);
        L.batch = ops::gather_batch(cmd, pool, P.batch, L.clusters);
        for (size_t k = 0; k < kinds; ++k)
            L.codes.push_back(ops::pool_codes(cmd, pool, P.codes[k], L.clusters, 3 * shift));
        L.rows = level_rows(P.rows, s);
        sort_level(L);
    }
    return st;
}

}  // namespace pg::nn

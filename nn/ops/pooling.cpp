#include "nn/ops/pooling.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "nn/ops/serialize.h"
#include "shaders/nn/index_shared.glsl"

namespace pg::nn::ops {

namespace detail {

void number_runs(vk::CommandList& cmd, IndexState& state, const Tensor& keys, const Tensor& starts,
                 const Tensor& info, uint32_t n) {
    cmd.dispatch("nn/pool_runs", {keys, starts}, gpu::CountPush{n}, groups(n));
    state.scan.exclusive(cmd, *starts.buffer, *starts.buffer, n, info.buffer.get(), PG_INFO_COUNT * 4);
}

}  // namespace detail

namespace {

void expect_clusters(const char* op, const Clusters& c, int64_t points) {
    if (!c.cluster.defined() || !c.ptr.defined() || !c.head.defined() || !c.members.defined())
        throw std::invalid_argument(std::string(op) + ": the clusters are not defined (call pool_clusters first)");
    if (c.cluster.dim(0) != points)
        throw std::invalid_argument(std::string(op) + ": the clusters cover " + std::to_string(c.cluster.dim(0)) +
                                    " points, the input has " + std::to_string(points) + " rows");
}

}  // namespace

Clusters pool_clusters(vk::CommandList& cmd, Pool& pool, const Tensor& code, int shift) {
    return pool_clusters(cmd, pool, code, shift, 64);
}

Clusters pool_clusters(vk::CommandList& cmd, Pool& pool, const Tensor& code, int shift, int code_bits) {
    detail::expect("pool_clusters", "code", code, DType::U64, {-1});
    if (shift < 0 || shift > 63)
        throw std::invalid_argument("pool_clusters: shift " + std::to_string(shift) + " is outside [0, 63]");
    if (code_bits < 0 || code_bits > 64)
        throw std::invalid_argument("pool_clusters: code_bits " + std::to_string(code_bits) + " is outside [0, 64]");
    const int64_t n = code.dim(0);
    Clusters c{pool.empty({n}, DType::I32), pool.empty({n}, DType::I32), pool.empty({n + 1}, DType::I32),
               pool.empty({n}, DType::I32), 0};
    if (n == 0) {
        cmd.fill(*c.ptr.buffer, 0, 0, 4);
        c.head.shape = {0};
        return c;
    }
    const uint32_t count = uint32_t(n);
    detail::IndexState& state = detail::index_state(pool.context());
    Tensor keys = pool.empty({n}, DType::U64), starts = pool.empty({n}, DType::U32);
    Tensor info = detail::info_tensor(cmd, pool);
    cmd.dispatch("nn/serialize_keys", {code, keys, c.members}, gpu::ShiftPush{count, uint32_t(shift), 1, 0},
                 detail::groups(count));
    state.sort.sort(cmd, *keys.buffer, *c.members.buffer, count, uint32_t(std::max(code_bits - shift, 0)),
                    sort::KeyWidth::Bits64);
    detail::number_runs(cmd, state, keys, starts, info, count);
    cmd.dispatch("nn/pool_scatter", {keys, starts, c.members, c.cluster, c.ptr, c.head}, gpu::CountPush{count},
                 detail::groups(count));
    c.count = detail::submit_and_read_info(cmd, state, info)[PG_INFO_COUNT];
    c.ptr.shape = {c.count + 1};
    c.head.shape = {c.count};
    return c;
}

Tensor segment_max(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Clusters& clusters) {
    detail::expect("segment_max", "x", x, DType::F32, {-1, -1});
    expect_clusters("segment_max", clusters, x.dim(0));
    const int64_t m = clusters.count, channels = x.dim(1);
    Tensor y = pool.empty({m, channels}, DType::F32);
    if (m == 0 || channels == 0) return y;
    cmd.dispatch("nn/segment_max", {x, clusters.members, clusters.ptr, y},
                 gpu::SegmentMaxPush{uint32_t(m), uint32_t(channels)}, detail::groups(uint64_t(m * channels)));
    return y;
}

Tensor pool_codes(vk::CommandList& cmd, Pool& pool, const Tensor& code, const Clusters& clusters, int shift) {
    detail::expect("pool_codes", "code", code, DType::U64, {-1});
    expect_clusters("pool_codes", clusters, code.dim(0));
    if (shift < 0 || shift > 63)
        throw std::invalid_argument("pool_codes: shift " + std::to_string(shift) + " is outside [0, 63]");
    const int64_t m = clusters.count;
    Tensor out = pool.empty({m}, DType::U64);
    if (m == 0) return out;
    cmd.dispatch("nn/pool_codes", {code, clusters.head, out}, gpu::ShiftPush{uint32_t(m), uint32_t(shift), 1, 0},
                 detail::groups(uint64_t(m)));
    return out;
}

Tensor pool_grid(vk::CommandList& cmd, Pool& pool, const Tensor& grid, const Clusters& clusters, int shift_bits) {
    detail::expect("pool_grid", "grid", grid, DType::I32, {-1, 3});
    expect_clusters("pool_grid", clusters, grid.dim(0));
    if (shift_bits < 0 || shift_bits > 31)
        throw std::invalid_argument("pool_grid: shift_bits " + std::to_string(shift_bits) + " is outside [0, 31]");
    const int64_t m = clusters.count;
    Tensor out = pool.empty({m, 3}, DType::I32);
    if (m == 0) return out;
    cmd.dispatch("nn/pool_grid", {grid, clusters.head, out}, gpu::ShiftPush{uint32_t(m), uint32_t(shift_bits), 3, 0},
                 detail::groups(uint64_t(m) * 3));
    return out;
}

Tensor gather_batch(vk::CommandList& cmd, Pool& pool, const Tensor& batch, const Clusters& clusters) {
    detail::expect("gather_batch", "batch", batch, DType::I32, {-1});
    expect_clusters("gather_batch", clusters, batch.dim(0));
    const int64_t m = clusters.count;
    Tensor out = pool.empty({m}, DType::I32);
    if (m == 0) return out;
    cmd.dispatch("nn/pool_grid", {batch, clusters.head, out}, gpu::ShiftPush{uint32_t(m), 0, 1, 0},
                 detail::groups(uint64_t(m)));
    return out;
}

}  // namespace pg::nn::ops

#include "nn/ops/voxelize.h"

#include <stdexcept>
#include <string>

#include "nn/ops/pooling.h"
#include "nn/ops/serialize.h"
#include "shaders/nn/index_shared.glsl"

namespace pg::nn::ops {

namespace detail {

SortedGrid sort_grid(vk::CommandList& cmd, Pool& pool, IndexState& state, const Tensor& grid, const Tensor& batch,
                     int key_bits) {
    if (key_bits < 1 || key_bits > 64)
        throw std::invalid_argument("sort_grid: key_bits " + std::to_string(key_bits) + " is outside [1, 64]");
    const int64_t n = grid.dim(0);
    const uint32_t count = uint32_t(n);
    SortedGrid s{pool.empty({n}, DType::U64), pool.empty({n}, DType::U32), info_tensor(cmd, pool)};
    cmd.dispatch("nn/voxel_bounds", {grid, batch, s.info}, gpu::CountPush{count}, groups(count));
    cmd.dispatch("nn/voxel_keys", {grid, batch, s.info, s.keys, s.points}, gpu::KeyPush{count, uint32_t(key_bits)},
                 groups(count));
    // The widths are known on the GPU only; a caller that knows a bound saves the passes over
    // digits that are zero in every key (a 4-bit pass each).
    state.sort.sort(cmd, *s.keys.buffer, *s.points.buffer, count, uint32_t(key_bits), sort::KeyWidth::Bits64);
    return s;
}

}  // namespace detail

Voxels voxelize(vk::CommandList& cmd, Pool& pool, const Tensor& grid, const Tensor& batch, int key_bits) {
    detail::expect("voxelize", "grid", grid, DType::I32, {-1, 3});
    const int64_t n = grid.dim(0);
    detail::expect("voxelize", "batch", batch, DType::I32, {n});
    Voxels v{pool.empty({n, 3}, DType::I32), pool.empty({n}, DType::I32), pool.empty({n}, DType::I32),
             pool.empty({n}, DType::I32), 0};
    if (n == 0) return v;
    const uint32_t count = uint32_t(n);
    detail::IndexState& state = detail::index_state(pool.context());
    detail::SortedGrid sorted = detail::sort_grid(cmd, pool, state, grid, batch, key_bits);
    Tensor starts = pool.empty({n}, DType::U32);
    detail::number_runs(cmd, state, sorted.keys, starts, sorted.info, count);
    cmd.dispatch("nn/voxel_scatter",
                 {sorted.keys, starts, sorted.points, grid, batch, v.inverse, v.first, v.grid, v.batch},
                 gpu::CountPush{count}, detail::groups(count));
    const std::vector<uint32_t> info = detail::submit_and_read_info(cmd, state, sorted.info);
    if (info[PG_INFO_FLAGS] & PG_FLAG_NEGATIVE)
        throw std::invalid_argument("voxelize: grid and batch entries must be >= 0");
    if (info[PG_INFO_FLAGS] & PG_FLAG_OVERFLOW)
        throw std::invalid_argument("voxelize: grid maxima (" + std::to_string(info[PG_INFO_MAX_X]) + ", " +
                                    std::to_string(info[PG_INFO_MAX_Y]) + ", " + std::to_string(info[PG_INFO_MAX_Z]) +
                                    ") and batch maximum " + std::to_string(info[PG_INFO_MAX_BATCH]) +
                                    " need more than " + std::to_string(key_bits) + " key bits");
    v.count = info[PG_INFO_COUNT];
    v.grid.shape = {v.count, 3};
    v.batch.shape = {v.count};
    v.first.shape = {v.count};
    return v;
}

}  // namespace pg::nn::ops

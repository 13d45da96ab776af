#include "nn/ops/neighbors.h"

#include <stdexcept>
#include <string>

#include "nn/ops/serialize.h"
#include "nn/ops/voxelize.h"
#include "shaders/nn/index_shared.glsl"

namespace pg::nn::ops {

Tensor neighbor_map(vk::CommandList& cmd, Pool& pool, const Tensor& grid, const Tensor& batch, int kernel,
                    int key_bits) {
    detail::expect("neighbor_map", "grid", grid, DType::I32, {-1, 3});
    const int64_t n = grid.dim(0);
    detail::expect("neighbor_map", "batch", batch, DType::I32, {n});
    if (kernel != 3 && kernel != 5)
        throw std::invalid_argument("neighbor_map: kernel " + std::to_string(kernel) + " is not 3 or 5");
    const int64_t k = kernel;
    Tensor nbr = pool.empty({n, k * k * k}, DType::I32);
    if (n == 0) return nbr;
    detail::IndexState& state = detail::index_state(pool.context());
    detail::SortedGrid sorted = detail::sort_grid(cmd, pool, state, grid, batch, key_bits);
    cmd.dispatch("nn/neighbors_search", {grid, batch, sorted.info, sorted.keys, sorted.points, nbr},
                 gpu::NeighborPush{uint32_t(n), uint32_t(k)}, detail::groups(uint64_t(n * k * k)));
    return nbr;
}

}  // namespace pg::nn::ops

#include "nn/train/drop_path.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

#include "shaders/nn/grad_shared.glsl"

namespace pg::nn::train {

Tensor drop_path_mask(vk::CommandList& cmd, Pool& pool, int64_t rows, double rate, std::mt19937_64& rng) {
    if (!(rate >= 0 && rate < 1)) throw std::invalid_argument("drop path: the rate must be in [0, 1)");
    const float keep = float(1.0 / (1.0 - rate));
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<float> mask(static_cast<size_t>(rows));
    for (float& m : mask) m = u(rng) < rate ? 0.0f : keep;
    Tensor t = pool.empty({rows});
    constexpr size_t kChunk = 16384;  // vkCmdUpdateBuffer takes at most 64 KiB
    for (size_t i = 0; i < mask.size(); i += kChunk)
        cmd.update(*t.buffer, mask.data() + i, std::min(kChunk, mask.size() - i) * sizeof(float), i * sizeof(float));
    return t;
}

Tensor scale_rows(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Tensor& scale) {
    if (x.dtype != DType::F32 || x.shape.size() != 2 || scale.dtype != DType::F32 || scale.shape.size() != 1 ||
        scale.dim(0) != x.dim(0))
        throw std::invalid_argument("scale_rows: x " + x.shape_string() + " and scale " + scale.shape_string() +
                                    " must be f32 [R, C] and [R]");
    Tensor y = pool.empty(x.shape);
    const uint64_t n = uint64_t(x.numel());
    if (n == 0) return y;
    if (n > 0xFFFFFFFFull) throw std::invalid_argument("scale_rows: tensor too large for 32-bit indexing");
    const grad::gpu::ScaleRowsPush push{uint32_t(n), uint32_t(x.dim(1))};
    cmd.dispatch("nn/scale_rows", {x, scale, y}, push, vk::ceil_div(n, PG_GRAD_THREADS));
    return y;
}

}  // namespace pg::nn::train

#pragma once
// PTv3's serialized window attention (Pointcept SerializedAttention without relative
// position encoding), as one tiled GPU kernel.
#include "nn/tensor.h"

namespace pg::nn::ops {

// qkv: [N, 3C] f32 in point order, columns [q | k | v], head h on channels [h*D, (h+1)*D) of
// each (D = C / heads, one of 8, 16, 32, 64). order: [N] i32, the point at each serialized
// position. offsets: [B+1] i32 on the device, positions offsets[b] .. offsets[b+1]-1 are
// cloud b (offsets[B] must equal N). Within cloud b (n_b positions), local position l attends
// to the min(patch, n_b) positions from offsets[b] + (n_b <= patch ? 0 :
// min(floor(l / patch) * patch, n_b - patch)): windows of `patch`, the last one pulled back
// to end with the cloud, as the release's padding does. Returns softmax(scale * q k^T) v per
// head, [N, C] f32 in point order (the proj Linear is the caller's).
Tensor window_attention(vk::CommandList& cmd, Pool& pool, const Tensor& qkv, const Tensor& order,
                        const Tensor& offsets, int heads, int patch, float scale);

}  // namespace pg::nn::ops

#pragma once
// CPU references for nn::ops::window_attention, in double.
#include <cstdint>
#include <vector>

namespace pg::test::ref {

// The window rule applied directly: in cloud b, local position l attends to the min(patch, n_b)
// positions from offsets[b] + (n_b <= patch ? 0 : min(floor(l / patch) * patch, n_b - patch)).
// qkv is [N, 3C] in point order; the result is [N, C] in point order.
std::vector<double> window_attention(const std::vector<float>& qkv, const std::vector<int32_t>& order,
                                     const std::vector<int32_t>& offsets, int heads, int patch, double scale);

// The release's literal route (Pointcept SerializedAttention.get_padding_and_inverse): pad each
// cloud larger than the patch to a multiple of it, filling the last window with a copy of the
// previous window's tail, run plain softmax attention per padded window (the cu_seqlens of the
// flash path), and unpad through the inverse.
std::vector<double> window_attention_padded(const std::vector<float>& qkv, const std::vector<int32_t>& order,
                                            const std::vector<int32_t>& offsets, int heads, int patch,
                                            double scale);

}  // namespace pg::test::ref

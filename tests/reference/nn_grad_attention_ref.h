#pragma once
// CPU references for the backward of PTv3's window attention (nn/train/grad_attention.h), in
// double: a forward on double inputs (so central finite differences can check the backward) and
// the backward written from the definition, scattering dk, dv over the windows.
#include <cstdint>
#include <vector>

namespace pg::test::ref::grad {

// The forward of ref::window_attention on double qkv [N, 3C] (point order); out [N, C].
std::vector<double> window_attention_forward(const std::vector<double>& qkv, const std::vector<int32_t>& order,
                                             const std::vector<int32_t>& offsets, int heads, int patch,
                                             double scale);

// dqkv [N, 3C] = d(sum dout . out)/d(qkv) for dout [N, C] (point order).
std::vector<double> window_attention_backward(const std::vector<double>& qkv, const std::vector<int32_t>& order,
                                              const std::vector<int32_t>& offsets, int heads, int patch,
                                              double scale, const std::vector<double>& dout);

}  // namespace pg::test::ref::grad

#pragma once
// Deterministic reductions and argument checks shared by the backward ops (nn/train): column
// sums in two stages (chunk partials, then their sum in chunk order) whose chunking depends on
// the row count alone, so results are bit-identical from run to run.
#include <cstdint>
#include <string>
#include <vector>

#include "nn/tensor.h"

namespace pg::nn::grad::detail {

// Throws std::invalid_argument naming the op unless t is defined with the dtype and shape
// (-1: any size).
void expect(const char* op, const char* name, const Tensor& t, DType dtype, std::vector<int64_t> shape);
void expect_small(const char* op, uint64_t n);  // 32-bit indexing in the shaders

// Rows per chunk of a column reduction over `rows` rows (at most 256 chunks).
uint32_t rows_per_chunk(uint64_t rows);

// out[c] = scale * sum over the rows of the term of `mode` (PG_COLSUM_*, grad_shared.glsl) for
// a, b [rows, cols] and v; unused operands may be any tensor.
Tensor column_sums(vk::CommandList& cmd, Pool& pool, uint32_t mode, const Tensor& a, const Tensor& b, const Tensor& v,
                   uint64_t rows, uint64_t cols, float scale = 1.0f);

// out[i] = scale * sum over s < splits of part[s * len + i], for i < len.
void sum_partials(vk::CommandList& cmd, const Tensor& part, const Tensor& out, uint64_t len, uint64_t splits,
                  float scale = 1.0f);

}  // namespace pg::nn::grad::detail

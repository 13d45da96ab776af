#pragma once
// Submanifold sparse convolution over a rulebook: per kernel offset (tap), the list of
// (output row, input row) pairs the neighbour table holds. The convolution is then a GEMM per
// tap over that tap's pairs only (an output row appears at most once per tap, so no two pairs
// of a tap write one row); missing neighbours cost nothing. Each tap's products are added into
// y, one dispatch per tap, except on CPU drivers where taps x rows x channels is at most 4 M:
// there every tap runs in one dispatch into a slice per tap, added in tap order after
// (nn/conv_reduce), and the rulebook carries the schedule that sizes that dispatch. A rulebook
// depends only on the neighbour table:
// build it once per table and reuse it for every convolution over it.
#include "nn/tensor.h"

namespace pg::nn::ops {

struct Rulebook {
    Tensor nbr;     // [M, T] I32, the table it was built from
    Tensor pairs;   // U32 [T, M, 2]: tap t's (output row, input row) pairs, pairs[t][0, counts[t])
    Tensor counts;  // U32 [T]
    Tensor schedule;  // U32, small tables: the taps' row groups for the all-taps kernels (nn/conv_schedule)
    int64_t rows() const { return nbr.dim(0); }
    int64_t taps() const { return nbr.dim(1); }
};

// nbr [M, T] I32 as sparse_conv takes it (-1 = no neighbour). Recorded only, no host wait.
Rulebook build_rulebook(vk::CommandList& cmd, Pool& pool, const Tensor& nbr);

// sparse_conv (nn/ops/linear.h) over a prebuilt rulebook of its neighbour table: the same result
// up to rounding (each tap's products are summed apart, then added to the bias).
Tensor sparse_conv(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Rulebook& rules, const Tensor& w,
                   const Tensor& bias);

// Algorithm choice, for tests and benchmarks. Auto: the rulebook on CPU devices where its
// kernels fit (Cin % 16 == 0, Cout % 8 == 0) and on GPUs for tables of 65536 rows or more,
// else the gathered GEMM. Rulebook: wherever its kernels fit. Gathered: never the rulebook.
enum class ConvPath { Auto, Gathered, Rulebook };
void set_conv_path(ConvPath path);
ConvPath conv_path();

}  // namespace pg::nn::ops

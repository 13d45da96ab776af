#pragma once
// CPU references of the dense NN ops (nn/ops/linear.h, norm.h, elementwise.h): plain loops in
// double, row-major, shapes as the ops take them.
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace pg::test::ref {

// n values uniform in [lo, hi), reproducible from `seed`.
std::vector<float> random_uniform(std::size_t n, uint32_t seed, float lo = -1.0f, float hi = 1.0f);

// y[M,N] = x[M,K] w[N,K]^T + bias[N] + residual[M,N]; bias and residual may be empty.
std::vector<double> linear(const std::vector<float>& x, const std::vector<float>& w, const std::vector<float>& bias,
                           const std::vector<float>& residual, int64_t M, int64_t K, int64_t N);

// Sum of |x[m,k] w[n,k]| + |bias| + |residual| per output: the scale f32 rounding errors grow with.
std::vector<double> linear_magnitude(const std::vector<float>& x, const std::vector<float>& w,
                                     const std::vector<float>& bias, const std::vector<float>& residual, int64_t M,
                                     int64_t K, int64_t N);

// A of the gathered GEMM: a[m, t*cin + c] = x[nbr[m,t], c], zero where nbr is -1.
std::vector<float> gather_conv_input(const std::vector<float>& x, const std::vector<int32_t>& nbr, int64_t M,
                                     int64_t T, int64_t cin);

// The rulebook of a neighbour table (nn/ops/sparse_conv.h): per tap t, the pairs
// (m, nbr[m,t]) for every m with nbr[m,t] >= 0, rows ascending.
std::vector<std::vector<std::pair<int32_t, int32_t>>> rulebook(const std::vector<int32_t>& nbr, int64_t M, int64_t T);

std::vector<double> layer_norm(const std::vector<float>& x, const std::vector<float>& gamma,
                               const std::vector<float>& beta, int64_t M, int64_t C, double eps);

std::vector<double> batch_norm(const std::vector<float>& x, const std::vector<float>& mean,
                               const std::vector<float>& var, const std::vector<float>& gamma,
                               const std::vector<float>& beta, int64_t M, int64_t C, double eps, bool gelu);

double gelu(double x);  // 0.5 x (1 + erf(x / sqrt 2))

// Rows of `words` 32-bit words: y[r] = x[idx[r]].
std::vector<uint32_t> gather_rows(const std::vector<uint32_t>& x, const std::vector<int32_t>& idx, int64_t words);

std::vector<double> add_gathered(const std::vector<float>& a, const std::vector<float>& x,
                                 const std::vector<int32_t>& idx, int64_t C);

}  // namespace pg::test::ref

#pragma once
// CPU references of the backward ops (nn/train/grad_ops.h) and of the forwards they differentiate,
// all in double so central finite differences of the forwards can check the backwards. Written
// from the definitions, without the GPU's shortcuts (the conv's dx scatters over the pairs of the
// map instead of using its symmetry).
#include <cstdint>
#include <functional>
#include <vector>

#include "tests/reference/nn_index_ref.h"

namespace pg::test::ref::grad {

using Vec = std::vector<double>;

Vec to_double(const std::vector<float>& v);
double dot(const Vec& a, const Vec& b);

// g[i] = (f(x + eps e_i) - f(x - eps e_i)) / (2 eps): central differences of a scalar function.
Vec numeric_gradient(const std::function<double(const Vec&)>& f, Vec x, double eps = 1e-6);

// Worst |got - want| / (rel * (1 + |want|)): <= 1 passes.
double worst_error(const std::vector<float>& got, const Vec& want, double rel);
double worst_error(const Vec& got, const Vec& want, double rel);
// Worst |got - want| / (rel * (1 + max_j |want_j|)): relative to the tensor's scale. For sums over
// many rows (dw, db, dgamma, dbeta), whose f32 rounding follows the size of the terms, not of a
// result that happens to cancel to near 0.
double worst_error_normwise(const std::vector<float>& got, const Vec& want, double rel);

// y[M,N] = x[M,K] w[N,K]^T + b[N] (b may be empty).
Vec linear_forward(const Vec& x, const Vec& w, const Vec& b, int64_t M, int64_t K, int64_t N);
struct LinearGrads {
    Vec dx, dw, db;
};
LinearGrads linear_backward(const Vec& x, const Vec& w, const Vec& dy, int64_t M, int64_t K, int64_t N);

// Submanifold conv: y[q,o] = b[o] + sum_t sum_c w[o, t*cin + c] x[nbr[q,t], c]; x [P,cin], nbr [P,T].
Vec conv_forward(const Vec& x, const std::vector<int32_t>& nbr, const Vec& w, const Vec& b, int64_t P, int64_t T,
                 int64_t cin, int64_t cout);
LinearGrads conv_backward(const Vec& x, const std::vector<int32_t>& nbr, const Vec& w, const Vec& dy, int64_t P,
                          int64_t T, int64_t cin, int64_t cout);
// nbr[q,t] = p  <=>  nbr[p, T-1-t] = q for every pair.
bool symmetric_map(const std::vector<int32_t>& nbr, int64_t P, int64_t T);

struct NormGrads {
    Vec dx, dgamma, dbeta;
};
Vec layer_norm_forward(const Vec& x, const Vec& gamma, const Vec& beta, int64_t M, int64_t C, double eps);
NormGrads layer_norm_backward(const Vec& x, const Vec& gamma, const Vec& dy, int64_t M, int64_t C, double eps);

// Training-mode BatchNorm: batch mean and biased variance per channel.
struct BatchNormTrain {
    Vec y, mean, var;
};
BatchNormTrain batch_norm_train(const Vec& x, const Vec& gamma, const Vec& beta, int64_t M, int64_t C, double eps);
// running = (1 - m) running + m batch, the variance unbiased.
void update_running_stats(Vec& running_mean, Vec& running_var, const Vec& mean, const Vec& var, int64_t M,
                          double momentum);
NormGrads batch_norm_backward(const Vec& x, const Vec& gamma, const Vec& dy, int64_t M, int64_t C, double eps);

Vec gelu_forward(const Vec& x);
Vec gelu_backward(const Vec& x, const Vec& dy);

// y[r] = x[idx[r]] on rows of C; backward sums dy into P rows.
Vec gather_rows_forward(const Vec& x, const std::vector<int32_t>& idx, int64_t C);
Vec gather_rows_backward(const Vec& dy, const std::vector<int32_t>& idx, int64_t P, int64_t C);

// y = a + x[idx].
Vec add_gathered_forward(const Vec& a, const Vec& x, const std::vector<int32_t>& idx, int64_t C);
struct AddGatheredGrads {
    Vec da, dx;
};
AddGatheredGrads add_gathered_backward(const Vec& dy, const std::vector<int32_t>& idx, int64_t P, int64_t C);

// y[m] = max over the members of cluster m; backward routes dy to the max, the lowest index on ties.
Vec segment_max_forward(const Vec& x, int64_t C, const Clusters& clusters);
Vec segment_max_backward(const Vec& x, const Vec& dy, int64_t C, const Clusters& clusters);

// Mean softmax cross-entropy over the rows whose label is in [0, K) and not `ignore`.
struct CrossEntropy {
    double loss = 0;
    Vec dlogits;
    int64_t counted = 0, bad = 0;
};
CrossEntropy cross_entropy(const Vec& logits, const std::vector<int32_t>& labels, int64_t M, int64_t K, int32_t ignore);

// Lovasz-softmax as Berman et al.'s reference code writes it (flattened, classes present):
// per class, errors |fg - p| sorted descending (ties by row), the Lovasz gradient of the sorted
// foreground from cumulative sums, their dot product; the mean over classes present. Rows are
// counted as in cross_entropy. The gradient treats the sorted order as fixed (exact away from ties).
struct Lovasz {
    double loss = 0;
    Vec dlogits;
};
Lovasz lovasz_softmax(const Vec& logits, const std::vector<int32_t>& labels, int64_t M, int64_t K, int32_t ignore);

}  // namespace pg::test::ref::grad

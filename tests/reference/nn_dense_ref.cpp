#include "tests/reference/nn_dense_ref.h"

#include <cmath>
#include <random>

namespace pg::test::ref {

std::vector<float> random_uniform(std::size_t n, uint32_t seed, float lo, float hi) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> d(lo, hi);
    std::vector<float> v(n);
    for (auto& x : v) x = d(rng);
    return v;
}

std::vector<double> linear(const std::vector<float>& x, const std::vector<float>& w, const std::vector<float>& bias,
                           const std::vector<float>& residual, int64_t M, int64_t K, int64_t N) {
    std::vector<double> y(size_t(M * N));
    for (int64_t m = 0; m < M; ++m)
        for (int64_t n = 0; n < N; ++n) {
            double s = bias.empty() ? 0.0 : bias[size_t(n)];
            if (!residual.empty()) s += residual[size_t(m * N + n)];
            for (int64_t k = 0; k < K; ++k) s += double(x[size_t(m * K + k)]) * w[size_t(n * K + k)];
            y[size_t(m * N + n)] = s;
        }
    return y;
}

std::vector<double> linear_magnitude(const std::vector<float>& x, const std::vector<float>& w,
                                     const std::vector<float>& bias, const std::vector<float>& residual, int64_t M,
                                     int64_t K, int64_t N) {
    std::vector<double> y(size_t(M * N));
    for (int64_t m = 0; m < M; ++m)
        for (int64_t n = 0; n < N; ++n) {
            double s = bias.empty() ? 0.0 : std::fabs(bias[size_t(n)]);
            if (!residual.empty()) s += std::fabs(residual[size_t(m * N + n)]);
            for (int64_t k = 0; k < K; ++k) s += std::fabs(double(x[size_t(m * K + k)]) * w[size_t(n * K + k)]);
            y[size_t(m * N + n)] = s;
        }
    return y;
}

std::vector<float> gather_conv_input(const std::vector<float>& x, const std::vector<int32_t>& nbr, int64_t M,
                                     int64_t T, int64_t cin) {
    std::vector<float> a(size_t(M * T * cin), 0.0f);
    for (int64_t m = 0; m < M; ++m)
        for (int64_t t = 0; t < T; ++t) {
            const int32_t j = nbr[size_t(m * T + t)];
            if (j < 0) continue;
            for (int64_t c = 0; c < cin; ++c) a[size_t((m * T + t) * cin + c)] = x[size_t(j * cin + c)];
        }
    return a;
}

std::vector<std::vector<std::pair<int32_t, int32_t>>> rulebook(const std::vector<int32_t>& nbr, int64_t M, int64_t T) {
    std::vector<std::vector<std::pair<int32_t, int32_t>>> pairs(static_cast<size_t>(T));
    for (int64_t m = 0; m < M; ++m)
        for (int64_t t = 0; t < T; ++t)
            if (const int32_t j = nbr[size_t(m * T + t)]; j >= 0) pairs[size_t(t)].push_back({int32_t(m), j});
    return pairs;
}

std::vector<double> layer_norm(const std::vector<float>& x, const std::vector<float>& gamma,
                               const std::vector<float>& beta, int64_t M, int64_t C, double eps) {
    std::vector<double> y(size_t(M * C));
    for (int64_t m = 0; m < M; ++m) {
        const float* r = &x[size_t(m * C)];
        double mean = 0, var = 0;
        for (int64_t c = 0; c < C; ++c) mean += r[c];
        mean /= double(C);
        for (int64_t c = 0; c < C; ++c) var += (r[c] - mean) * (r[c] - mean);
        var /= double(C);
        const double inv = 1.0 / std::sqrt(var + eps);
        for (int64_t c = 0; c < C; ++c) y[size_t(m * C + c)] = (r[c] - mean) * inv * gamma[size_t(c)] + beta[size_t(c)];
    }
    return y;
}

double gelu(double x) { return 0.5 * x * std::erfc(-x / std::sqrt(2.0)); }

std::vector<double> batch_norm(const std::vector<float>& x, const std::vector<float>& mean,
                               const std::vector<float>& var, const std::vector<float>& gamma,
                               const std::vector<float>& beta, int64_t M, int64_t C, double eps, bool use_gelu) {
    std::vector<double> y(size_t(M * C));
    for (int64_t m = 0; m < M; ++m)
        for (int64_t c = 0; c < C; ++c) {
            const size_t i = size_t(m * C + c), k = size_t(c);
            const double v = (x[i] - double(mean[k])) / std::sqrt(double(var[k]) + eps) * gamma[k] + beta[k];
            y[i] = use_gelu ? gelu(v) : v;
        }
    return y;
}

std::vector<uint32_t> gather_rows(const std::vector<uint32_t>& x, const std::vector<int32_t>& idx, int64_t words) {
    std::vector<uint32_t> y(idx.size() * size_t(words));
    for (size_t r = 0; r < idx.size(); ++r)
        for (int64_t c = 0; c < words; ++c) y[r * size_t(words) + size_t(c)] = x[size_t(idx[r] * words + c)];
    return y;
}

std::vector<double> add_gathered(const std::vector<float>& a, const std::vector<float>& x,
                                 const std::vector<int32_t>& idx, int64_t C) {
    std::vector<double> y(a.size());
    for (size_t r = 0; r < idx.size(); ++r)
        for (int64_t c = 0; c < C; ++c)
            y[r * size_t(C) + size_t(c)] = double(a[r * size_t(C) + size_t(c)]) + x[size_t(idx[r] * C + c)];
    return y;
}

}  // namespace pg::test::ref

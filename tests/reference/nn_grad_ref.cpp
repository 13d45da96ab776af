#include "tests/reference/nn_grad_ref.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace pg::test::ref::grad {

namespace {
size_t at(int64_t r, int64_t c, int64_t cols) { return size_t(r * cols + c); }
}  // namespace

Vec to_double(const std::vector<float>& v) { return Vec(v.begin(), v.end()); }

double dot(const Vec& a, const Vec& b) {
    double s = 0;
    for (size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
    return s;
}

Vec numeric_gradient(const std::function<double(const Vec&)>& f, Vec x, double eps) {
    Vec g(x.size());
    for (size_t i = 0; i < x.size(); ++i) {
        const double keep = x[i];
        x[i] = keep + eps;
        const double up = f(x);
        x[i] = keep - eps;
        const double down = f(x);
        x[i] = keep;
        g[i] = (up - down) / (2 * eps);
    }
    return g;
}

double worst_error(const Vec& got, const Vec& want, double rel) {
    if (got.size() != want.size()) return INFINITY;
    double worst = 0;
    for (size_t i = 0; i < got.size(); ++i)
        worst = std::max(worst, std::fabs(got[i] - want[i]) / (rel * (1.0 + std::fabs(want[i]))));
    return worst;
}

double worst_error_normwise(const std::vector<float>& got, const Vec& want, double rel) {
    if (got.size() != want.size()) return INFINITY;
    double scale = 0, worst = 0;
    for (double w : want) scale = std::max(scale, std::fabs(w));
    for (size_t i = 0; i < got.size(); ++i) worst = std::max(worst, std::fabs(double(got[i]) - want[i]));
    return worst / (rel * (1.0 + scale));
}

double worst_error(const std::vector<float>& got, const Vec& want, double rel) {
    return worst_error(to_double(got), want, rel);
}

Vec linear_forward(const Vec& x, const Vec& w, const Vec& b, int64_t M, int64_t K, int64_t N) {
    Vec y(size_t(M * N));
    for (int64_t m = 0; m < M; ++m)
        for (int64_t n = 0; n < N; ++n) {
            double s = b.empty() ? 0.0 : b[size_t(n)];
            for (int64_t k = 0; k < K; ++k) s += x[at(m, k, K)] * w[at(n, k, K)];
            y[at(m, n, N)] = s;
        }
    return y;
}

LinearGrads linear_backward(const Vec& x, const Vec& w, const Vec& dy, int64_t M, int64_t K, int64_t N) {
    LinearGrads g{Vec(size_t(M * K)), Vec(size_t(N * K)), Vec(size_t(N))};
    for (int64_t m = 0; m < M; ++m)
        for (int64_t n = 0; n < N; ++n) {
            const double d = dy[at(m, n, N)];
            g.db[size_t(n)] += d;
            for (int64_t k = 0; k < K; ++k) {
                g.dx[at(m, k, K)] += d * w[at(n, k, K)];
                g.dw[at(n, k, K)] += d * x[at(m, k, K)];
            }
        }
    return g;
}

Vec conv_forward(const Vec& x, const std::vector<int32_t>& nbr, const Vec& w, const Vec& b, int64_t P, int64_t T,
                 int64_t cin, int64_t cout) {
    Vec y(size_t(P * cout));
    for (int64_t q = 0; q < P; ++q)
        for (int64_t o = 0; o < cout; ++o) {
            double s = b.empty() ? 0.0 : b[size_t(o)];
            for (int64_t t = 0; t < T; ++t) {
                const int32_t p = nbr[at(q, t, T)];
                if (p < 0) continue;
                for (int64_t c = 0; c < cin; ++c) s += w[at(o, t * cin + c, T * cin)] * x[at(p, c, cin)];
            }
            y[at(q, o, cout)] = s;
        }
    return y;
}

LinearGrads conv_backward(const Vec& x, const std::vector<int32_t>& nbr, const Vec& w, const Vec& dy, int64_t P,
                          int64_t T, int64_t cin, int64_t cout) {
    LinearGrads g{Vec(size_t(P * cin)), Vec(size_t(cout * T * cin)), Vec(size_t(cout))};
    for (int64_t q = 0; q < P; ++q)
        for (int64_t o = 0; o < cout; ++o) {
            const double d = dy[at(q, o, cout)];
            g.db[size_t(o)] += d;
            for (int64_t t = 0; t < T; ++t) {
                const int32_t p = nbr[at(q, t, T)];
                if (p < 0) continue;
                for (int64_t c = 0; c < cin; ++c) {
                    g.dx[at(p, c, cin)] += d * w[at(o, t * cin + c, T * cin)];
                    g.dw[at(o, t * cin + c, T * cin)] += d * x[at(p, c, cin)];
                }
            }
        }
    return g;
}

bool symmetric_map(const std::vector<int32_t>& nbr, int64_t P, int64_t T) {
    for (int64_t q = 0; q < P; ++q)
        for (int64_t t = 0; t < T; ++t) {
            const int32_t p = nbr[at(q, t, T)];
            if (p >= 0 && nbr[at(p, T - 1 - t, T)] != q) return false;
        }
    return true;
}

Vec layer_norm_forward(const Vec& x, const Vec& gamma, const Vec& beta, int64_t M, int64_t C, double eps) {
    Vec y(size_t(M * C));
    for (int64_t m = 0; m < M; ++m) {
        double mean = 0, var = 0;
        for (int64_t c = 0; c < C; ++c) mean += x[at(m, c, C)];
        mean /= double(C);
        for (int64_t c = 0; c < C; ++c) var += (x[at(m, c, C)] - mean) * (x[at(m, c, C)] - mean);
        const double inv = 1.0 / std::sqrt(var / double(C) + eps);
        for (int64_t c = 0; c < C; ++c)
            y[at(m, c, C)] = (x[at(m, c, C)] - mean) * inv * gamma[size_t(c)] + beta[size_t(c)];
    }
    return y;
}

NormGrads layer_norm_backward(const Vec& x, const Vec& gamma, const Vec& dy, int64_t M, int64_t C, double eps) {
    NormGrads g{Vec(size_t(M * C)), Vec(size_t(C)), Vec(size_t(C))};
    Vec xhat(static_cast<size_t>(C));
    for (int64_t m = 0; m < M; ++m) {
        double mean = 0, var = 0;
        for (int64_t c = 0; c < C; ++c) mean += x[at(m, c, C)];
        mean /= double(C);
        for (int64_t c = 0; c < C; ++c) var += (x[at(m, c, C)] - mean) * (x[at(m, c, C)] - mean);
        const double inv = 1.0 / std::sqrt(var / double(C) + eps);
        // d/dx of xhat = (x - mean) inv, with mean and inv depending on the row.
        double sg = 0, sgx = 0;
        for (int64_t c = 0; c < C; ++c) {
            xhat[size_t(c)] = (x[at(m, c, C)] - mean) * inv;
            const double gi = dy[at(m, c, C)] * gamma[size_t(c)];
            sg += gi;
            sgx += gi * xhat[size_t(c)];
            g.dgamma[size_t(c)] += dy[at(m, c, C)] * xhat[size_t(c)];
            g.dbeta[size_t(c)] += dy[at(m, c, C)];
        }
        for (int64_t c = 0; c < C; ++c)
            g.dx[at(m, c, C)] =
                inv * (dy[at(m, c, C)] * gamma[size_t(c)] - sg / double(C) - xhat[size_t(c)] * sgx / double(C));
    }
    return g;
}

BatchNormTrain batch_norm_train(const Vec& x, const Vec& gamma, const Vec& beta, int64_t M, int64_t C, double eps) {
    BatchNormTrain r{Vec(size_t(M * C)), Vec(size_t(C)), Vec(size_t(C))};
    for (int64_t c = 0; c < C; ++c) {
        double mean = 0, var = 0;
        for (int64_t m = 0; m < M; ++m) mean += x[at(m, c, C)];
        mean /= double(M);
        for (int64_t m = 0; m < M; ++m) var += (x[at(m, c, C)] - mean) * (x[at(m, c, C)] - mean);
        var /= double(M);
        r.mean[size_t(c)] = mean;
        r.var[size_t(c)] = var;
        const double inv = 1.0 / std::sqrt(var + eps);
        for (int64_t m = 0; m < M; ++m)
            r.y[at(m, c, C)] = (x[at(m, c, C)] - mean) * inv * gamma[size_t(c)] + beta[size_t(c)];
    }
    return r;
}

void update_running_stats(Vec& running_mean, Vec& running_var, const Vec& mean, const Vec& var, int64_t M,
                          double momentum) {
    for (size_t c = 0; c < mean.size(); ++c) {
        running_mean[c] = (1 - momentum) * running_mean[c] + momentum * mean[c];
        running_var[c] = (1 - momentum) * running_var[c] + momentum * var[c] * double(M) / double(M - 1);
    }
}

NormGrads batch_norm_backward(const Vec& x, const Vec& gamma, const Vec& dy, int64_t M, int64_t C, double eps) {
    const BatchNormTrain f = batch_norm_train(x, gamma, Vec(size_t(C), 0.0), M, C, eps);
    NormGrads g{Vec(size_t(M * C)), Vec(size_t(C)), Vec(size_t(C))};
    for (int64_t c = 0; c < C; ++c) {
        const double inv = 1.0 / std::sqrt(f.var[size_t(c)] + eps);
        double sdy = 0, sdyx = 0;
        for (int64_t m = 0; m < M; ++m) {
            const double xhat = (x[at(m, c, C)] - f.mean[size_t(c)]) * inv;
            sdy += dy[at(m, c, C)];
            sdyx += dy[at(m, c, C)] * xhat;
        }
        g.dbeta[size_t(c)] = sdy;
        g.dgamma[size_t(c)] = sdyx;
        for (int64_t m = 0; m < M; ++m) {
            const double xhat = (x[at(m, c, C)] - f.mean[size_t(c)]) * inv;
            g.dx[at(m, c, C)] =
                gamma[size_t(c)] * inv * (dy[at(m, c, C)] - sdy / double(M) - xhat * sdyx / double(M));
        }
    }
    return g;
}

Vec gelu_forward(const Vec& x) {
    Vec y(x.size());
    for (size_t i = 0; i < x.size(); ++i) y[i] = 0.5 * x[i] * std::erfc(-x[i] / std::sqrt(2.0));
    return y;
}

Vec gelu_backward(const Vec& x, const Vec& dy) {
    Vec dx(x.size());
    for (size_t i = 0; i < x.size(); ++i) {
        const double cdf = 0.5 * std::erfc(-x[i] / std::sqrt(2.0));
        const double pdf = std::exp(-0.5 * x[i] * x[i]) / std::sqrt(2.0 * M_PI);
        dx[i] = dy[i] * (cdf + x[i] * pdf);
    }
    return dx;
}

Vec gather_rows_forward(const Vec& x, const std::vector<int32_t>& idx, int64_t C) {
    Vec y(idx.size() * size_t(C));
    for (size_t r = 0; r < idx.size(); ++r)
        for (int64_t c = 0; c < C; ++c) y[at(int64_t(r), c, C)] = x[at(idx[r], c, C)];
    return y;
}

Vec gather_rows_backward(const Vec& dy, const std::vector<int32_t>& idx, int64_t P, int64_t C) {
    Vec dx(size_t(P * C), 0.0);
    for (size_t r = 0; r < idx.size(); ++r)
        for (int64_t c = 0; c < C; ++c) dx[at(idx[r], c, C)] += dy[at(int64_t(r), c, C)];
    return dx;
}

Vec add_gathered_forward(const Vec& a, const Vec& x, const std::vector<int32_t>& idx, int64_t C) {
    Vec y = gather_rows_forward(x, idx, C);
    for (size_t i = 0; i < y.size(); ++i) y[i] += a[i];
    return y;
}

AddGatheredGrads add_gathered_backward(const Vec& dy, const std::vector<int32_t>& idx, int64_t P, int64_t C) {
    return {dy, gather_rows_backward(dy, idx, P, C)};
}

Vec segment_max_forward(const Vec& x, int64_t C, const Clusters& clusters) {
    const size_t M = clusters.ptr.size() - 1;
    Vec y(M * size_t(C), -INFINITY);
    for (size_t m = 0; m < M; ++m)
        for (int32_t j = clusters.ptr[m]; j < clusters.ptr[m + 1]; ++j)
            for (int64_t c = 0; c < C; ++c)
                y[at(int64_t(m), c, C)] = std::max(y[at(int64_t(m), c, C)], x[at(clusters.members[size_t(j)], c, C)]);
    return y;
}

Vec segment_max_backward(const Vec& x, const Vec& dy, int64_t C, const Clusters& clusters) {
    Vec dx(x.size(), 0.0);
    const size_t M = clusters.ptr.size() - 1;
    for (size_t m = 0; m < M; ++m)
        for (int64_t c = 0; c < C; ++c) {
            int32_t best = -1;
            for (int32_t j = clusters.ptr[m]; j < clusters.ptr[m + 1]; ++j) {
                const int32_t p = clusters.members[size_t(j)];
                const double v = x[at(p, c, C)];
                if (best < 0 || v > x[at(best, c, C)] || (v == x[at(best, c, C)] && p < best)) best = p;
            }
            if (best >= 0) dx[at(best, c, C)] = dy[at(int64_t(m), c, C)];
        }
    return dx;
}

CrossEntropy cross_entropy(const Vec& logits, const std::vector<int32_t>& labels, int64_t M, int64_t K,
                           int32_t ignore) {
    CrossEntropy r;
    r.dlogits.assign(size_t(M * K), 0.0);
    double sum = 0;
    for (int64_t m = 0; m < M; ++m) {
        const int32_t label = labels[size_t(m)];
        if (label == ignore) continue;
        if (label < 0 || label >= K) {
            ++r.bad;
            continue;
        }
        ++r.counted;
        double mx = -INFINITY;
        for (int64_t k = 0; k < K; ++k) mx = std::max(mx, logits[at(m, k, K)]);
        double s = 0;
        for (int64_t k = 0; k < K; ++k) s += std::exp(logits[at(m, k, K)] - mx);
        sum += mx + std::log(s) - logits[at(m, label, K)];
        for (int64_t k = 0; k < K; ++k)
            r.dlogits[at(m, k, K)] = std::exp(logits[at(m, k, K)] - mx) / s - (k == label ? 1.0 : 0.0);
    }
    const double scale = 1.0 / double(std::max<int64_t>(r.counted, 1));
    r.loss = sum * scale;
    for (auto& d : r.dlogits) d *= scale;
    return r;
}

Lovasz lovasz_softmax(const Vec& logits, const std::vector<int32_t>& labels, int64_t M, int64_t K, int32_t ignore) {
    Lovasz r;
    r.dlogits.assign(size_t(M * K), 0.0);
    std::vector<int64_t> rows;
    for (int64_t m = 0; m < M; ++m)
        if (labels[size_t(m)] != ignore && labels[size_t(m)] >= 0 && labels[size_t(m)] < K) rows.push_back(m);
    const size_t n = rows.size();
    Vec prob(n * size_t(K));
    for (size_t i = 0; i < n; ++i) {
        const int64_t m = rows[i];
        double mx = -INFINITY, s = 0;
        for (int64_t k = 0; k < K; ++k) mx = std::max(mx, logits[at(m, k, K)]);
        for (int64_t k = 0; k < K; ++k) s += std::exp(logits[at(m, k, K)] - mx);
        for (int64_t k = 0; k < K; ++k) prob[i * size_t(K) + size_t(k)] = std::exp(logits[at(m, k, K)] - mx) / s;
    }
    // dloss / dp per counted row and class.
    Vec dprob(n * size_t(K), 0.0);
    int present = 0;
    for (int64_t c = 0; c < K; ++c) {
        Vec fg(n), err(n);
        for (size_t i = 0; i < n; ++i) {
            fg[i] = labels[size_t(rows[i])] == c ? 1.0 : 0.0;
            err[i] = std::fabs(fg[i] - prob[i * size_t(K) + size_t(c)]);
        }
        const double gts = std::accumulate(fg.begin(), fg.end(), 0.0);
        if (gts == 0) continue;
        ++present;
        std::vector<size_t> order(n);
        std::iota(order.begin(), order.end(), size_t(0));
        std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return err[a] > err[b]; });
        double cum_fg = 0, cum_bg = 0, prev = 0;
        for (size_t j = 0; j < n; ++j) {
            const size_t i = order[j];
            cum_fg += fg[i];
            cum_bg += 1.0 - fg[i];
            const double jaccard = 1.0 - (gts - cum_fg) / (gts + cum_bg);
            const double grad = jaccard - prev;
            prev = jaccard;
            r.loss += err[i] * grad;
            dprob[i * size_t(K) + size_t(c)] = grad * (fg[i] > 0 ? -1.0 : 1.0);
        }
    }
    if (present == 0) return r;
    r.loss /= present;
    for (size_t i = 0; i < n; ++i) {
        const double* p = &prob[i * size_t(K)];
        const double* dp = &dprob[i * size_t(K)];
        double dot = 0;
        for (int64_t k = 0; k < K; ++k) dot += dp[k] * p[k];
        for (int64_t k = 0; k < K; ++k) r.dlogits[at(rows[i], k, K)] = p[k] * (dp[k] - dot) / present;
    }
    return r;
}

}  // namespace pg::test::ref::grad

#include "tests/reference/nn_grad_attention_ref.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>

namespace pg::test::ref::grad {

namespace {

// Calls visit(queries, keys) for every run of positions sharing one window (the window rule of
// ref::window_attention), with serialized positions.
void for_each_window(const std::vector<int32_t>& offsets, int patch,
                     const std::function<void(const std::vector<int64_t>&, const std::vector<int64_t>&)>& visit) {
    for (size_t b = 0; b + 1 < offsets.size(); ++b) {
        const int64_t first = offsets[b], nb = offsets[b + 1] - offsets[b];
        auto start_of = [&](int64_t l) { return first + (nb <= patch ? 0 : std::min(l / patch * patch, nb - patch)); };
        for (int64_t l = 0; l < nb;) {
            const int64_t start = start_of(l);
            std::vector<int64_t> queries, keys;
            for (; l < nb && start_of(l) == start; ++l) queries.push_back(first + l);
            for (int64_t j = 0; j < std::min<int64_t>(patch, nb); ++j) keys.push_back(start + j);
            visit(queries, keys);
        }
    }
}

int channels_of(const std::vector<double>& qkv, const std::vector<int32_t>& order, const std::vector<int32_t>& offsets,
                int heads) {
    const size_t n = order.size();
    if (n == 0 || qkv.size() % (3 * n) != 0) throw std::invalid_argument("ref::grad::window_attention: qkv not [N, 3C]");
    const int channels = int(qkv.size() / (3 * n));
    if (heads <= 0 || channels % heads != 0)
        throw std::invalid_argument("ref::grad::window_attention: channels % heads != 0");
    if (offsets.size() < 2 || offsets.front() != 0 || size_t(offsets.back()) != n)
        throw std::invalid_argument("ref::grad::window_attention: offsets must run from 0 to N");
    return channels;
}

// Softmax probabilities of one query row over the keys, for head h.
void probabilities(const std::vector<double>& qkv, size_t qrow, const std::vector<size_t>& krows, int channels, int h,
                   int d_head, double scale, std::vector<double>& p) {
    p.assign(krows.size(), 0.0);
    double top = -INFINITY;
    for (size_t j = 0; j < krows.size(); ++j) {
        double s = 0;
        for (int d = 0; d < d_head; ++d)
            s += qkv[qrow + size_t(h * d_head + d)] * qkv[krows[j] + size_t(channels + h * d_head + d)];
        p[j] = s * scale;
        top = std::max(top, p[j]);
    }
    double sum = 0;
    for (double& s : p) sum += (s = std::exp(s - top));
    for (double& s : p) s /= sum;
}

std::vector<size_t> rows_of(const std::vector<int64_t>& positions, const std::vector<int32_t>& order, size_t stride) {
    std::vector<size_t> rows;
    for (int64_t p : positions) rows.push_back(size_t(order[size_t(p)]) * stride);
    return rows;
}

}  // namespace

std::vector<double> window_attention_forward(const std::vector<double>& qkv, const std::vector<int32_t>& order,
                                             const std::vector<int32_t>& offsets, int heads, int patch,
                                             double scale) {
    const int channels = channels_of(qkv, order, offsets, heads);
    const int d_head = channels / heads;
    const size_t stride = size_t(3 * channels);
    std::vector<double> out(order.size() * size_t(channels), 0.0), p;
    for_each_window(offsets, patch, [&](const std::vector<int64_t>& queries, const std::vector<int64_t>& keys) {
        const std::vector<size_t> krows = rows_of(keys, order, stride);
        for (int64_t qp : queries) {
            const size_t point = size_t(order[size_t(qp)]);
            for (int h = 0; h < heads; ++h) {
                probabilities(qkv, point * stride, krows, channels, h, d_head, scale, p);
                for (int d = 0; d < d_head; ++d) {
                    double v = 0;
                    for (size_t j = 0; j < krows.size(); ++j)
                        v += p[j] * qkv[krows[j] + size_t(2 * channels + h * d_head + d)];
                    out[point * size_t(channels) + size_t(h * d_head + d)] = v;
                }
            }
        }
    });
    return out;
}

std::vector<double> window_attention_backward(const std::vector<double>& qkv, const std::vector<int32_t>& order,
                                              const std::vector<int32_t>& offsets, int heads, int patch,
                                              double scale, const std::vector<double>& dout) {
    const int channels = channels_of(qkv, order, offsets, heads);
    if (dout.size() != order.size() * size_t(channels))
        throw std::invalid_argument("ref::grad::window_attention_backward: dout is not [N, C]");
    const int d_head = channels / heads;
    const size_t stride = size_t(3 * channels);
    std::vector<double> dqkv(qkv.size(), 0.0), p, dp;
    for_each_window(offsets, patch, [&](const std::vector<int64_t>& queries, const std::vector<int64_t>& keys) {
        const std::vector<size_t> krows = rows_of(keys, order, stride);
        for (int64_t qp : queries) {
            const size_t point = size_t(order[size_t(qp)]), qrow = point * stride;
            for (int h = 0; h < heads; ++h) {
                const size_t c0 = size_t(h * d_head);
                const double* g = &dout[point * size_t(channels) + c0];
                probabilities(qkv, qrow, krows, channels, h, d_head, scale, p);
                // out = sum_j p_j v_j: dv_j += p_j g, dp_j = g . v_j; softmax: ds_j = p_j (dp_j - sum_k p_k dp_k).
                dp.assign(krows.size(), 0.0);
                double mean = 0;
                for (size_t j = 0; j < krows.size(); ++j) {
                    for (int d = 0; d < d_head; ++d) {
                        dqkv[krows[j] + size_t(2 * channels) + c0 + size_t(d)] += p[j] * g[d];
                        dp[j] += g[d] * qkv[krows[j] + size_t(2 * channels) + c0 + size_t(d)];
                    }
                    mean += p[j] * dp[j];
                }
                for (size_t j = 0; j < krows.size(); ++j) {
                    const double ds = p[j] * (dp[j] - mean) * scale;  // d loss / d (q . k_j)
                    for (int d = 0; d < d_head; ++d) {
                        dqkv[qrow + c0 + size_t(d)] += ds * qkv[krows[j] + size_t(channels) + c0 + size_t(d)];
                        dqkv[krows[j] + size_t(channels) + c0 + size_t(d)] += ds * qkv[qrow + c0 + size_t(d)];
                    }
                }
            }
        }
    });
    return dqkv;
}

}  // namespace pg::test::ref::grad

#include "tests/reference/nn_attention_ref.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pg::test::ref {

namespace {

// Softmax attention of the queries at positions `queries` over the keys at positions `keys`
// (serialized positions, mapped to points through `order`); results go to the query's point.
void attend(const std::vector<float>& qkv, const std::vector<int32_t>& order, int channels, int heads, double scale,
            const std::vector<int64_t>& queries, const std::vector<int64_t>& keys, std::vector<double>& out) {
    const int d_head = channels / heads;
    const size_t stride = size_t(3 * channels);
    std::vector<double> logits(keys.size());
    for (int64_t qp : queries) {
        const size_t qrow = size_t(order[size_t(qp)]) * stride;
        for (int h = 0; h < heads; ++h) {
            double top = -INFINITY;
            for (size_t j = 0; j < keys.size(); ++j) {
                const size_t krow = size_t(order[size_t(keys[j])]) * stride + size_t(channels);
                double s = 0;
                for (int d = 0; d < d_head; ++d)
                    s += double(qkv[qrow + size_t(h * d_head + d)]) * double(qkv[krow + size_t(h * d_head + d)]);
                logits[j] = s * scale;
                top = std::max(top, logits[j]);
            }
            double sum = 0;
            for (double& s : logits) sum += (s = std::exp(s - top));
            double* dst = &out[size_t(order[size_t(qp)]) * size_t(channels) + size_t(h * d_head)];
            for (int d = 0; d < d_head; ++d) {
                double v = 0;
                for (size_t j = 0; j < keys.size(); ++j)
                    v += logits[j] * double(qkv[size_t(order[size_t(keys[j])]) * stride + size_t(2 * channels) +
                                                size_t(h * d_head + d)]);
                dst[d] = v / sum;
            }
        }
    }
}

int check_shapes(const std::vector<float>& qkv, const std::vector<int32_t>& order, const std::vector<int32_t>& offsets,
                 int heads) {
    const size_t n = order.size();
    if (n == 0 || qkv.size() % (3 * n) != 0) throw std::invalid_argument("ref::window_attention: qkv is not [N, 3C]");
    const int channels = int(qkv.size() / (3 * n));
    if (channels % heads != 0) throw std::invalid_argument("ref::window_attention: channels % heads != 0");
    if (offsets.size() < 2 || offsets.front() != 0 || size_t(offsets.back()) != n)
        throw std::invalid_argument("ref::window_attention: offsets must run from 0 to N");
    return channels;
}

}  // namespace

std::vector<double> window_attention(const std::vector<float>& qkv, const std::vector<int32_t>& order,
                                     const std::vector<int32_t>& offsets, int heads, int patch, double scale) {
    const int channels = check_shapes(qkv, order, offsets, heads);
    std::vector<double> out(order.size() * size_t(channels), 0.0);
    for (size_t b = 0; b + 1 < offsets.size(); ++b) {
        const int64_t first = offsets[b], nb = offsets[b + 1] - offsets[b];
        auto start_of = [&](int64_t l) { return first + (nb <= patch ? 0 : std::min(l / patch * patch, nb - patch)); };
        // The rule per position; runs of positions with the same window share one key list.
        for (int64_t l = 0; l < nb;) {
            const int64_t start = start_of(l);
            std::vector<int64_t> queries, keys;
            for (; l < nb && start_of(l) == start; ++l) queries.push_back(first + l);
            for (int64_t j = 0; j < std::min<int64_t>(patch, nb); ++j) keys.push_back(start + j);
            attend(qkv, order, channels, heads, scale, queries, keys, out);
        }
    }
    return out;
}

std::vector<double> window_attention_padded(const std::vector<float>& qkv, const std::vector<int32_t>& order,
                                            const std::vector<int32_t>& offsets, int heads, int patch,
                                            double scale) {
    const int channels = check_shapes(qkv, order, offsets, heads);
    const size_t clouds = offsets.size() - 1;
    // bincount, bincount_pad, _offset_pad as in get_padding_and_inverse.
    std::vector<int64_t> count(clouds), count_pad(clouds), offset_pad(clouds + 1, 0);
    for (size_t b = 0; b < clouds; ++b) {
        count[b] = offsets[b + 1] - offsets[b];
        count_pad[b] = count[b] > patch ? (count[b] + patch - 1) / patch * patch : count[b];
        offset_pad[b + 1] = offset_pad[b] + count_pad[b];
    }
    std::vector<int64_t> pad(size_t(offset_pad.back())), unpad(order.size());
    for (size_t i = 0; i < pad.size(); ++i) pad[i] = int64_t(i);
    for (size_t i = 0; i < unpad.size(); ++i) unpad[i] = int64_t(i);
    std::vector<int64_t> cu_seqlens;
    for (size_t b = 0; b < clouds; ++b) {
        for (int64_t i = offsets[b]; i < offsets[b + 1]; ++i) unpad[size_t(i)] += offset_pad[b] - offsets[b];
        if (count[b] != count_pad[b]) {
            // pad[end - K + r : end] = pad[end - 2K + r : end - K]
            const int64_t end = offset_pad[b + 1], r = count[b] % patch;
            for (int64_t i = end - patch + r; i < end; ++i) pad[size_t(i)] = pad[size_t(i - patch)];
        }
        for (int64_t i = offset_pad[b]; i < offset_pad[b + 1]; ++i) pad[size_t(i)] -= offset_pad[b] - offsets[b];
        for (int64_t s = offset_pad[b]; s < offset_pad[b + 1]; s += patch) cu_seqlens.push_back(s);
    }
    cu_seqlens.push_back(offset_pad.back());

    // Attention over the padded sequence: padded slot i holds serialized position pad[i].
    std::vector<int32_t> padded_order(pad.size());
    for (size_t i = 0; i < pad.size(); ++i) padded_order[i] = order[size_t(pad[i])];
    const size_t stride = size_t(3 * channels);
    std::vector<float> padded_qkv(pad.size() * stride);
    for (size_t i = 0; i < pad.size(); ++i)
        std::copy_n(&qkv[size_t(padded_order[i]) * stride], stride, &padded_qkv[i * stride]);
    std::vector<int32_t> identity(pad.size());
    for (size_t i = 0; i < pad.size(); ++i) identity[i] = int32_t(i);
    std::vector<double> padded_out(pad.size() * size_t(channels), 0.0);
    for (size_t w = 0; w + 1 < cu_seqlens.size(); ++w) {
        std::vector<int64_t> slots;
        for (int64_t i = cu_seqlens[w]; i < cu_seqlens[w + 1]; ++i) slots.push_back(i);
        attend(padded_qkv, identity, channels, heads, scale, slots, slots, padded_out);
    }
    // feat[inverse]: point order[p] takes padded row unpad[p].
    std::vector<double> out(order.size() * size_t(channels));
    for (size_t p = 0; p < order.size(); ++p)
        std::copy_n(&padded_out[size_t(unpad[p]) * size_t(channels)], channels,
                    &out[size_t(order[p]) * size_t(channels)]);
    return out;
}

}  // namespace pg::test::ref

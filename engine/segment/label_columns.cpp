#include "engine/segment/label_columns.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace pg::seg {

namespace {
constexpr uint32_t kNone = 0xFFFFFFFFu;
}

LabelColumns::LabelColumns(uint32_t nodes, uint32_t labels, bool sparse) : nodes_(nodes), labels_(labels), sparse_(sparse) {
    if (!sparse_) {
        dense_.assign(size_t(nodes) * labels, 0.0f);
        return;
    }
    kept_label_.assign(size_t(nodes) * kKept, kNone);
    kept_value_.assign(size_t(nodes) * kKept, 0.0f);
    sum_.assign(nodes, 0.0f);
    best_.assign(nodes, 0.0f);
    arg_.assign(nodes, -1);
}

LabelColumns LabelColumns::dense(std::vector<float> x, uint32_t labels) {
    LabelColumns c;
    if (labels == 0 || x.size() % labels != 0)
        throw std::invalid_argument("label columns: " + std::to_string(x.size()) + " values do not divide into " +
                                    std::to_string(labels) + " labels");
    c.nodes_ = uint32_t(x.size() / labels);
    c.labels_ = labels;
    c.dense_ = std::move(x);
    return c;
}

float LabelColumns::at(uint32_t i, uint32_t l) const {
    if (!sparse_) return dense_[size_t(i) * labels_ + l];
    for (uint32_t s = 0; s < kKept; ++s)
        if (kept_label_[size_t(i) * kKept + s] == l) return kept_value_[size_t(i) * kKept + s];
    return 0.0f;
}

bool LabelColumns::any_positive(uint32_t i) const {
    if (!sparse_) {
        for (uint32_t l = 0; l < labels_; ++l)
            if (dense_[size_t(i) * labels_ + l] > 0) return true;
        return false;
    }
    for (uint32_t s = 0; s < kKept; ++s)
        if (kept_label_[size_t(i) * kKept + s] != kNone && kept_value_[size_t(i) * kKept + s] > 0) return true;
    return false;
}

void LabelColumns::read(uint32_t base, uint32_t count, uint32_t width, std::vector<float>& out) const {
    out.assign(size_t(nodes_) * width, 0.0f);
    if (!sparse_) {
        for (uint32_t i = 0; i < nodes_; ++i)
            for (uint32_t l = 0; l < count; ++l) out[size_t(i) * width + l] = dense_[size_t(i) * labels_ + base + l];
        return;
    }
    for (uint32_t i = 0; i < nodes_; ++i)
        for (uint32_t s = 0; s < kKept; ++s) {
            const uint32_t l = kept_label_[size_t(i) * kKept + s];
            if (l != kNone && l >= base && l < base + count) out[size_t(i) * width + (l - base)] = kept_value_[size_t(i) * kKept + s];
        }
}

void LabelColumns::write(uint32_t base, uint32_t count, uint32_t width, const std::vector<float>& in) {
    if (!sparse_) {
        for (uint32_t i = 0; i < nodes_; ++i)
            for (uint32_t l = 0; l < count; ++l) dense_[size_t(i) * labels_ + base + l] = in[size_t(i) * width + l];
        return;
    }
    for (uint32_t i = 0; i < nodes_; ++i) {
        if (base == 0) clear_node(i);
        for (uint32_t l = 0; l < count; ++l) add(i, base + l, in[size_t(i) * width + l]);
    }
}

void LabelColumns::set_node(uint32_t i, const float* values) {
    if (!sparse_) {
        std::copy_n(values, labels_, &dense_[size_t(i) * labels_]);
        return;
    }
    clear_node(i);
    for (uint32_t l = 0; l < labels_; ++l) add(i, l, values[l]);
}

void LabelColumns::copy_node(uint32_t i, const LabelColumns& from, uint32_t j) {
    if (from.labels_ != labels_ || from.sparse_ != sparse_)
        throw std::logic_error("label columns: copying a node between different layouts");
    if (!sparse_) {
        std::copy_n(&from.dense_[size_t(j) * labels_], labels_, &dense_[size_t(i) * labels_]);
        return;
    }
    std::copy_n(&from.kept_label_[size_t(j) * kKept], kKept, &kept_label_[size_t(i) * kKept]);
    std::copy_n(&from.kept_value_[size_t(j) * kKept], kKept, &kept_value_[size_t(i) * kKept]);
    sum_[i] = from.sum_[j];
    best_[i] = from.best_[j];
    arg_[i] = from.arg_[j];
}

void LabelColumns::clear_node(uint32_t i) {
    std::fill_n(&kept_label_[size_t(i) * kKept], kKept, kNone);
    std::fill_n(&kept_value_[size_t(i) * kKept], kKept, 0.0f);
    sum_[i] = 0.0f;
    best_[i] = 0.0f;
    arg_[i] = -1;
}

void LabelColumns::add(uint32_t i, uint32_t l, float v) {
    // The dense rule's arithmetic, label by label: a running sum of max(0, v) and the first
    // label of largest value.
    const float p = std::max(0.0f, v);
    sum_[i] += p;
    if (p > best_[i]) best_[i] = p, arg_[i] = int32_t(l);
    if (!(v > 0)) return;  // what is kept starts a later solve: zero is the default there
    uint32_t* label = &kept_label_[size_t(i) * kKept];
    float* value = &kept_value_[size_t(i) * kKept];
    uint32_t slot = 0;  // a free slot, else the smallest value (the latest label of equals: earlier ones stay)
    for (uint32_t s = 0; s < kKept; ++s) {
        if (label[s] == kNone) {
            slot = s;
            break;
        }
        if (value[s] < value[slot] || (value[s] == value[slot] && label[s] > label[slot])) slot = s;
    }
    if (label[slot] != kNone && !(v > value[slot])) return;
    label[slot] = l;
    value[slot] = v;
}

WalkLabels LabelColumns::most_likely(const std::vector<uint8_t>* reached) const {
    WalkLabels w{std::vector<int32_t>(nodes_, -1), std::vector<float>(nodes_, 0.0f)};
    for (uint32_t i = 0; i < nodes_; ++i) {
        if (reached && !(*reached)[i]) continue;
        float sum = 0, best = 0;
        int32_t arg = -1;
        if (sparse_) {
            sum = sum_[i], best = best_[i], arg = arg_[i];
        } else {
            for (uint32_t l = 0; l < labels_; ++l) {
                const float v = std::max(0.0f, dense_[size_t(i) * labels_ + l]);
                sum += v;
                if (v > best) best = v, arg = int32_t(l);
            }
        }
        w.share[i] = sum > 0 ? best / sum : 0.0f;
        w.arg[i] = sum > 0 ? arg : -1;
    }
    return w;
}

std::vector<float> LabelColumns::take_dense() {
    if (sparse_) throw std::logic_error("label columns: a sparse layout has no dense matrix");
    nodes_ = 0;
    return std::move(dense_);
}

}  // namespace pg::seg

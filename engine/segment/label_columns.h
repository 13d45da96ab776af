#pragma once
// A walk's values per node and label (its probabilities, or a start for them): all of them,
// nodes x labels floats, or past a label count only each node's kKept largest, so that memory
// stays flat however many objects a scene holds. Either way each node's most likely label and
// its share of the node's sum are exact: columns are written in label order, and a held-sparse
// node keeps its running sum and its argmax as the dense rule takes them.
#include <cstdint>
#include <vector>

namespace pg::seg {

// Each node's most likely label and that label's share of the (non-negative) sum; -1 where the
// sum is 0 or the node is not reached.
struct WalkLabels {
    std::vector<int32_t> arg;
    std::vector<float> share;
};

class LabelColumns {
public:
    static constexpr uint32_t kKept = 16;  // labels a sparse node keeps (its largest values)

    LabelColumns() = default;
    // All zero; sparse when `sparse` (then values past a node's kKept largest are dropped).
    LabelColumns(uint32_t nodes, uint32_t labels, bool sparse);
    // A dense node-major matrix taken over (x.size() == nodes x labels).
    static LabelColumns dense(std::vector<float> x, uint32_t labels);

    bool empty() const { return nodes_ == 0; }
    bool sparse() const { return sparse_; }
    uint32_t nodes() const { return nodes_; }
    uint32_t labels() const { return labels_; }

    float at(uint32_t i, uint32_t l) const;  // 0 where a sparse node keeps nothing for l
    bool any_positive(uint32_t i) const;
    // Columns [base, base + count) of every node into `out`, `width` floats a node (the rest 0).
    void read(uint32_t base, uint32_t count, uint32_t width, std::vector<float>& out) const;
    // The same columns written from `in`. Sparse: call in label order, from label 0 on.
    void write(uint32_t base, uint32_t count, uint32_t width, const std::vector<float>& in);
    // Node i's values: `values` holds one per label (sparse keeps the largest), or node j's of `from`.
    void set_node(uint32_t i, const float* values);
    void copy_node(uint32_t i, const LabelColumns& from, uint32_t j);

    WalkLabels most_likely(const std::vector<uint8_t>* reached) const;
    std::vector<float> take_dense();  // dense only: the matrix, leaving this empty

private:
    void clear_node(uint32_t i);
    void add(uint32_t i, uint32_t l, float v);  // sparse: label l's value, labels in order

    uint32_t nodes_ = 0, labels_ = 0;
    bool sparse_ = false;
    std::vector<float> dense_;      // node-major
    // Sparse, per node: kKept (label, value) pairs by slot (kNone: free), the running sum of the
    // non-negative values, the argmax so far (-1: none) and its value.
    std::vector<uint32_t> kept_label_;
    std::vector<float> kept_value_, sum_, best_;
    std::vector<int32_t> arg_;
};

}  // namespace pg::seg

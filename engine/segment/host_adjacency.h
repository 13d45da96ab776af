#pragma once
// The kNN graph's symmetric adjacency as the host holds it (KnnGraph's cached copy): what the
// host-side solvers (the widest-path flood, the multigrid hierarchy) read. No Vulkan here.
#include <cstdint>
#include <vector>

namespace pg::seg {

// W + W^T as CSR rows: per node its neighbours either way and the edge weights (KnnGraph's
// host copy, in the device's row order), and each node's degree as the device computed it.
struct HostAdjacency {
    std::vector<uint32_t> rows;  // nodes + 1 starts into columns / weights
    std::vector<uint32_t> columns;
    std::vector<float> weights;
    std::vector<float> degree;
    uint32_t nodes() const { return rows.empty() ? 0 : uint32_t(rows.size() - 1); }
};

}  // namespace pg::seg

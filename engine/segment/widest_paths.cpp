#include "engine/segment/widest_paths.h"

#include <algorithm>
#include <queue>
#include <utility>

#include "shaders/segment/graph_shared.h"

namespace pg::seg {

WidestPaths widest_paths(const HostAdjacency& a, const std::vector<int32_t>& seed) {
    const uint32_t n = a.nodes();
    WidestPaths out{std::vector<int32_t>(n, -1), std::vector<float>(n, 0.0f)};
    // (width, node): a node is final when it leaves the heap at its recorded width.
    std::priority_queue<std::pair<float, uint32_t>> heap;
    for (uint32_t i = 0; i < n; ++i)
        if (seed[i] >= 0) out.label[i] = seed[i], out.width[i] = gpu::kForestSeedValue;
    // The flood starts at the free nodes next to a seed, not at every seed: after a walk almost
    // every node is a seed, and only the border matters.
    for (uint32_t i = 0; i < n; ++i) {
        if (seed[i] >= 0) continue;
        for (uint32_t s = a.rows[i]; s < a.rows[i + 1]; ++s)
            if (const uint32_t j = a.columns[s]; seed[j] >= 0 && a.weights[s] > out.width[i])
                out.width[i] = a.weights[s], out.label[i] = seed[j];
        if (out.width[i] > 0) heap.push({out.width[i], i});
    }
    while (!heap.empty()) {
        const auto [w, i] = heap.top();
        heap.pop();
        if (w < out.width[i]) continue;  // a wider path reached it since
        for (uint32_t s = a.rows[i]; s < a.rows[i + 1]; ++s) {
            const uint32_t j = a.columns[s];
            if (seed[j] >= 0 || a.weights[s] <= 0) continue;
            if (const float v = std::min(w, a.weights[s]); v > out.width[j]) {
                out.width[j] = v, out.label[j] = out.label[i];
                heap.push({v, j});
            }
        }
    }
    return out;
}

}  // namespace pg::seg

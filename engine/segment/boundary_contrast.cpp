#include "engine/segment/boundary_contrast.h"

#include <cstddef>

namespace pg::seg {

std::vector<double> boundary_contrast(const HostAdjacency& graph, const std::vector<int32_t>& label, uint32_t labels) {
    std::vector<double> cut(labels, 0.0), inside(labels, 0.0), cut_edges(labels, 0.0), inside_edges(labels, 0.0);
    const uint32_t nodes = graph.nodes();
    for (uint32_t i = 0; i < nodes; ++i) {
        const int32_t l = label[i];
        if (l <= 0 || uint32_t(l) >= labels) continue;
        for (uint32_t e = graph.rows[i]; e < graph.rows[i + 1]; ++e) {
            const double w = graph.weights[e];
            if (label[graph.columns[e]] == l) inside[std::size_t(l)] += w, inside_edges[std::size_t(l)] += 1;
            else cut[std::size_t(l)] += w, cut_edges[std::size_t(l)] += 1;
        }
    }
    std::vector<double> contrast(labels, 0.0);
    for (uint32_t l = 1; l < labels; ++l)
        if (cut_edges[l] > 0 && inside[l] > 0) contrast[l] = (cut[l] / cut_edges[l]) / (inside[l] / inside_edges[l]);
    return contrast;
}

}  // namespace pg::seg

#pragma once
// CPU reference of the graph decoder (engine/segment/knn_graph, random_walker): brute-force k
// nearest neighbours, the same affinity per edge, the symmetric adjacency W + W^T, and the random
// walker's linear systems solved in double with Eigen's sparse conjugate gradient, the seeded
// maximum spanning forest by Kruskal. Written for clarity: O(n^2) neighbours, no grid.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "dataset/gaussian_cloud.h"

namespace pg::ref {

struct GraphNode {
    glm::vec3 position{0.0f}, colour{0.0f}, normal{0.0f};
    float opacity = 0, flatness = 0;
};

// Node attributes as graph_nodes.comp computes them, for cloud[domain[i]].
std::vector<GraphNode> graph_nodes(const data::GaussianCloud& cloud, const std::vector<uint32_t>& domain);

struct RefGraph {
    uint32_t k = 0;
    std::vector<uint32_t> neighbours;  // k per node, nearest first (ties: smaller index), 0xFFFFFFFF if fewer
    std::vector<float> distances;      // k per node
    std::vector<float> weights;        // k per node, 0 for empty slots
};

// The k nearest among the nodes within `radius` (the GPU's guaranteed search range).
RefGraph knn_graph(const std::vector<GraphNode>& nodes, uint32_t k, float radius, float beta_colour,
                   float beta_normal, float beta_distance);

// Solves, for every label, (L + Gamma) x = Gamma q + seed coupling over the unknown nodes of the
// symmetric graph W + W^T; seeds hold their indicator. Node-major result, labels per node.
std::vector<double> random_walk(const RefGraph& graph, uint32_t labels, const std::vector<int32_t>& seed,
                                const std::vector<float>& gamma, const std::vector<float>& prior);

struct RefForest {
    std::vector<int32_t> label;  // per node, -1 if no seed is reached
    std::vector<float> width;    // the widest path's weakest pair weight (4 at seeds, 0 if unreached)
};

// The seeded maximum spanning forest by Kruskal: edges of W + W^T from the strongest down, two
// trees joined unless both hold (different) seeds; a node takes its tree's seed label. The widths
// come from a separate widest-path search (a Dijkstra on max-min).
RefForest seeded_forest(const RefGraph& graph, const std::vector<int32_t>& seed);

}  // namespace pg::ref

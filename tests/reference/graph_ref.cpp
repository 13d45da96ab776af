#include "tests/reference/graph_ref.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <queue>

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/Sparse>

namespace pg::ref {

std::vector<GraphNode> graph_nodes(const data::GaussianCloud& cloud, const std::vector<uint32_t>& domain) {
    const double c0 = 0.28209479177387814;
    std::vector<GraphNode> out;
    for (uint32_t g : domain) {
        GraphNode n;
        n.position = cloud.mean[g];
        n.opacity = float(1.0 / (1.0 + std::exp(-double(cloud.opacity_logit[g]))));
        for (int c = 0; c < 3; ++c) n.colour[c] = float(std::clamp(0.5 + c0 * cloud.sh[size_t(g) * size_t(cloud.coeffs()) * 3 + size_t(c)], 0.0, 1.0));
        glm::vec3 s = cloud.log_scale[g];
        glm::vec4 q = cloud.rotation[g];  // w, x, y, z
        q /= glm::length(q);
        // Rotation matrix columns are the Gaussian's axes.
        glm::mat3 r(1 - 2 * (q.z * q.z + q.w * q.w), 2 * (q.y * q.z + q.x * q.w), 2 * (q.y * q.w - q.x * q.z),
                    2 * (q.y * q.z - q.x * q.w), 1 - 2 * (q.y * q.y + q.w * q.w), 2 * (q.z * q.w + q.x * q.y),
                    2 * (q.y * q.w + q.x * q.z), 2 * (q.z * q.w - q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z));
        int a = s.x <= s.y ? (s.x <= s.z ? 0 : 2) : (s.y <= s.z ? 1 : 2);
        float middle = a == 0 ? std::min(s.y, s.z) : a == 1 ? std::min(s.x, s.z) : std::min(s.x, s.y);
        n.normal = glm::normalize(r[a]);
        n.flatness = std::clamp((middle - s[a]) / float(std::log(10.0)), 0.0f, 1.0f);
        out.push_back(n);
    }
    return out;
}

RefGraph knn_graph(const std::vector<GraphNode>& nodes, uint32_t k, float radius, float beta_colour,
                   float beta_normal, float beta_distance) {
    const size_t n = nodes.size();
    RefGraph g;
    g.k = k;
    g.neighbours.assign(n * k, 0xFFFFFFFFu);
    g.distances.assign(n * k, 0.0f);
    g.weights.assign(n * k, 0.0f);
    std::vector<float> spacing(n, 0.0f);
    for (size_t i = 0; i < n; ++i) {
        std::vector<std::pair<float, uint32_t>> c;
        for (size_t j = 0; j < n; ++j) {
            if (j == i) continue;
            glm::vec3 d = nodes[j].position - nodes[i].position;
            float d2 = glm::dot(d, d);
            if (d2 <= radius * radius) c.push_back({d2, uint32_t(j)});
        }
        std::sort(c.begin(), c.end());
        size_t m = std::min<size_t>(k, c.size());
        double sum = 0;
        for (size_t t = 0; t < m; ++t) {
            g.neighbours[i * k + t] = c[t].second;
            g.distances[i * k + t] = std::sqrt(c[t].first);
            sum += g.distances[i * k + t];
        }
        spacing[i] = m ? float(sum / double(m)) : 0.0f;
    }
    for (size_t i = 0; i < n; ++i)
        for (uint32_t t = 0; t < k; ++t) {
            uint32_t j = g.neighbours[i * k + t];
            if (j == 0xFFFFFFFFu) continue;
            const GraphNode &a = nodes[i], &b = nodes[j];
            glm::vec3 dc = a.colour - b.colour;
            double s = std::max(std::sqrt(double(spacing[i]) * double(spacing[j])), 1e-12) * beta_distance;
            double r = g.distances[i * k + t] / s;
            double nn = glm::dot(a.normal, b.normal);
            double bend = a.flatness * b.flatness * (1 - nn * nn);
            g.weights[i * k + t] = float(std::exp(-beta_colour * glm::dot(dc, dc) - r * r - beta_normal * bend) *
                                         std::min(a.opacity, b.opacity));
        }
    return g;
}

std::vector<double> random_walk(const RefGraph& graph, uint32_t labels, const std::vector<int32_t>& seed,
                                const std::vector<float>& gamma, const std::vector<float>& prior) {
    const size_t n = seed.size(), k = graph.k;
    // Symmetric weights W + W^T as triplets over all nodes.
    std::vector<std::vector<std::pair<size_t, double>>> adj(n);
    for (size_t i = 0; i < n; ++i)
        for (size_t t = 0; t < k; ++t) {
            uint32_t j = graph.neighbours[i * k + t];
            if (j == 0xFFFFFFFFu) continue;
            adj[i].push_back({j, graph.weights[i * k + t]});
            adj[j].push_back({i, graph.weights[i * k + t]});
        }
    std::vector<long> unknown_of(n, -1);
    std::vector<size_t> unknowns;
    for (size_t i = 0; i < n; ++i)
        if (seed[i] < 0) unknown_of[i] = long(unknowns.size()), unknowns.push_back(i);
    const size_t u = unknowns.size();
    std::vector<Eigen::Triplet<double>> trip;
    Eigen::MatrixXd b = Eigen::MatrixXd::Zero(long(u), labels);
    for (size_t r = 0; r < u; ++r) {
        size_t i = unknowns[r];
        double diag = gamma.empty() ? 0.0 : gamma[i];
        for (uint32_t l = 0; l < labels; ++l) b(long(r), l) = diag * (prior.empty() ? 0.0 : prior[i * labels + l]);
        for (auto [j, w] : adj[i]) {
            diag += w;
            if (seed[j] >= 0) b(long(r), seed[j]) += w;
            else trip.push_back({long(r), unknown_of[j], -w});
        }
        trip.push_back({long(r), long(r), diag > 0 ? diag : 1.0});  // an isolated node keeps 0
    }
    Eigen::SparseMatrix<double> a{long(u), long(u)};
    a.setFromTriplets(trip.begin(), trip.end());
    Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> cg;
    cg.setTolerance(1e-10);
    cg.setMaxIterations(100000);
    cg.compute(a);
    Eigen::MatrixXd x = cg.solve(b);
    std::vector<double> out(n * labels, 0.0);
    for (size_t i = 0; i < n; ++i)
        for (uint32_t l = 0; l < labels; ++l)
            out[i * labels + l] = seed[i] >= 0 ? (seed[i] == int32_t(l) ? 1.0 : 0.0) : x(unknown_of[i], l);
    return out;
}

RefForest seeded_forest(const RefGraph& g, const std::vector<int32_t>& seed) {
    const uint32_t n = uint32_t(seed.size()), k = g.k;
    // The pairs of W + W^T: a pair listed both ways weighs both slots.
    std::map<std::pair<uint32_t, uint32_t>, float> pair_weight;
    for (uint32_t e = 0; e < g.neighbours.size(); ++e)
        if (const uint32_t j = g.neighbours[e]; j < n && g.weights[e] > 0)
            pair_weight[{std::min(e / k, j), std::max(e / k, j)}] += g.weights[e];
    struct Edge {
        uint32_t a, b;
        float w;
    };
    std::vector<Edge> edges;
    for (const auto& [p, w] : pair_weight) edges.push_back({p.first, p.second, w});
    std::stable_sort(edges.begin(), edges.end(), [](const Edge& a, const Edge& b) { return a.w > b.w; });
    std::vector<uint32_t> parent(n);
    std::vector<int32_t> tree_label(seed);
    for (uint32_t i = 0; i < n; ++i) parent[i] = i;
    auto root = [&](uint32_t i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    };
    for (const Edge& e : edges) {
        uint32_t a = root(e.a), b = root(e.b);
        if (a == b || (tree_label[a] >= 0 && tree_label[b] >= 0 && tree_label[a] != tree_label[b])) continue;
        parent[b] = a;
        if (tree_label[a] < 0) tree_label[a] = tree_label[b];
    }
    RefForest out;
    out.label.resize(n);
    for (uint32_t i = 0; i < n; ++i) out.label[i] = tree_label[root(i)];
    // Widest paths from all seeds at once: a max-heap Dijkstra where a path's value is its minimum.
    std::vector<std::vector<std::pair<uint32_t, float>>> adj(n);
    for (const Edge& e : edges) {
        adj[e.a].push_back({e.b, e.w});
        adj[e.b].push_back({e.a, e.w});
    }
    out.width.assign(n, 0.0f);
    std::priority_queue<std::pair<float, uint32_t>> heap;
    for (uint32_t i = 0; i < n; ++i)
        if (seed[i] >= 0) out.width[i] = 4.0f, heap.push({4.0f, i});
    while (!heap.empty()) {
        auto [w, i] = heap.top();
        heap.pop();
        if (w < out.width[i]) continue;
        for (auto [j, ew] : adj[i])
            if (float v = std::min(w, ew); v > out.width[j] && seed[j] < 0) out.width[j] = v, heap.push({v, j});
    }
    return out;
}

}  // namespace pg::ref

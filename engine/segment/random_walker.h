#pragma once
// The random walker (Grady 2006, with priors) on a KnnGraph, solved on the GPU: for each label
// l, x_l minimises sum_ij w_ij (x_il - x_jl)^2 + sum_i gamma_i (x_il - q_il)^2 with seeds held
// at their label's indicator, i.e. (L + Gamma) x_l = Gamma q_l + (seed coupling) over the
// unknown nodes. x_il is the probability that a walk from node i, stopped at a seed or (with
// rate gamma_i) by the prior, ends in label l. Jacobi-preconditioned conjugate gradient, all
// labels at once (up to kWalkMaxLabels columns per solve; more run as several); the host waits
// once every `check_every` iterations for the residuals.
#include <cstdint>
#include <vector>

#include "engine/segment/knn_graph.h"

namespace pg::seg {

struct WalkProblem {
    uint32_t labels = 0;            // label columns
    std::vector<int32_t> seed;      // per node: a label, or -1
    std::vector<float> gamma;       // per node unary strength (empty: none)
    std::vector<float> prior;       // node-major, labels per node (empty: none)
    std::vector<float> start;       // node-major starting point (empty: the prior, or 0)
};

struct WalkOptions {
    uint32_t max_iterations = 1000;
    float tolerance = 1e-3f;        // stop when r.z <= tolerance^2 x b.b/diag, for every label
    uint32_t check_every = 25;
};

struct WalkResult {
    std::vector<float> x;           // node-major, labels per node
    uint32_t iterations = 0;        // most over the column batches
    double residual = 0;            // largest final sqrt(r.z / (b.b/diag))
};

class RandomWalker {
public:
    explicit RandomWalker(vk::Context& ctx);
    WalkResult solve(const KnnGraph& graph, const WalkProblem& problem, const WalkOptions& options = {});
    const std::vector<vk::PassTiming>& timings() const { return timings_; }

private:
    vk::Context& ctx_;
    vk::CommandList cmd_;
    vk::Buffer seed_, gamma_, prior_, x_, b_, inv_diag_, r_, z_, p_, ap_, partials_, scalars_, edge_columns_, edge_weights_;
    std::vector<vk::PassTiming> timings_;
};

}  // namespace pg::seg

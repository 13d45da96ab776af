#pragma once
// The random walker (Grady 2006, with priors) on a KnnGraph, solved on the GPU: for each label
// l, x_l minimises sum_ij w_ij (x_il - x_jl)^2 + sum_i gamma_i (x_il - q_il)^2 with seeds held
// at their label's indicator, i.e. (L + Gamma) x_l = Gamma q_l + (seed coupling) over the
// unknown nodes. x_il is the probability that a walk from node i, stopped at a seed or (with
// rate gamma_i) by the prior, ends in label l. Preconditioned conjugate gradient, all labels at
// once (up to kWalkMaxLabels columns per solve; more run as several); the host waits once every
// `check_every` iterations for the residuals. The preconditioner is an aggregation multigrid
// V-cycle (walk_hierarchy, built on the host once per graph and seed set) or the diagonal.
#include <cstdint>
#include <vector>

#include "engine/segment/cancel.h"
#include "engine/segment/knn_graph.h"
#include "engine/segment/label_columns.h"
#include "engine/segment/walk_hierarchy.h"
#include "shaders/segment/graph_shared.h"

namespace pg::seg {

struct WalkProblem {
    uint32_t labels = 0;            // label columns
    std::vector<int32_t> seed;      // per node: a label, or -1
    std::vector<float> gamma;       // per node unary strength (empty: none)
    std::vector<float> prior;       // node-major, labels per node (empty: none)
    std::vector<float> start;       // node-major starting point (empty: the prior, or 0)
};

enum class WalkPreconditioner { Jacobi, Multigrid };

struct WalkOptions {
    uint32_t max_iterations = 1000;
    // Stop when r.z <= tolerance^2 x b.b/diag, for every label. 1e-2 gave the labels of 1e-3
    // (desk, residence, vehicles, real guitar: 99.99 % of nodes the same) in half the iterations.
    // 3e-2 moves a few labels but no score: the same 3D IoU (within 0.16 points per suite) on 42
    // scenes of four fresh seeds, with walk+forest and with the walk alone, and the real
    // guitar's labels byte for byte, in 5 iterations instead of 9.
    float tolerance = 3e-2f;
    uint32_t check_every = 0;       // iterations between the host's residual checks (0: 25 for
                                    // Jacobi, 1 for multigrid, which takes a handful in all)
    WalkPreconditioner preconditioner = WalkPreconditioner::Multigrid;
    // Multigrid: the coarse correction's scale. Over-correcting (1.2-1.4) took 12 dev scenes'
    // solves from 117 to 97 iterations, but leaves the constant mode of a weakly attached piece
    // (tiny energy: CG does not come back for it) 30 % off, and such a piece's probabilities pick
    // its label: on fresh seed 8317 a 4,944-Gaussian piece went to a car at every tolerance down
    // to 0.008 (at 1.0 it stays background from 0.03 on). So 1.
    float coarse_scale = 1.0f;
    HierarchyOptions hierarchy;
    const std::atomic<bool>* cancel = nullptr;  // set: the solve stops (Cancelled) at its next check
    // Past this many labels an answer held as LabelColumns keeps each node's few largest values
    // only (memory flat in the label count); the node-major vector API is always dense.
    uint32_t dense_labels = 32;
};

struct WalkResult {
    std::vector<float> x;           // node-major, labels per node
    uint32_t iterations = 0;        // most over the column batches
    double residual = 0;            // largest final sqrt(r.z / (b.b/diag))
    uint32_t levels = 0;            // multigrid levels (0: the Jacobi preconditioner)
    double hierarchy_ms = 0;        // host time building the multigrid hierarchy
    uint32_t jacobi_retries = 0;    // column batches multigrid made no progress on, solved again with Jacobi
    uint32_t range_retries = 0;     // of those, batches whose answer diverged past [-1, 2] (walk_values_outside)
    uint64_t out_of_range = 0;      // values still past it after Jacobi, clamped into [0, 1]
};

// Values of free nodes' label columns (node-major, `width` per node, the first `labels` used)
// outside [-slack, 1 + slack] or NaN. A random walker's probabilities obey the maximum
// principle; the solve's stopping slack leaves some a few hundredths outside [0, 1] (on seed
// 8317, 5 of 18 residence and desk scenes: 16-494 values past 0.05, which earlier sessions
// measured to cost no score), so the solver asks about slack 1: an answer that far off diverged.
uint64_t walk_values_outside(const std::vector<float>& columns, const std::vector<int32_t>& seed, uint32_t width,
                             uint32_t labels, float slack = 1.0f);
// Clamps those values into [0, 1] (NaN to 0) and returns how many there were.
uint64_t clamp_walk_values(std::vector<float>& columns, const std::vector<int32_t>& seed, uint32_t width,
                           uint32_t labels, float slack = 1.0f);

class RandomWalker {
public:
    explicit RandomWalker(vk::Context& ctx);
    WalkResult solve(const KnnGraph& graph, const WalkProblem& problem, const WalkOptions& options = {});
    // The same, taking the problem's starting point over as the answer's storage (a batch of
    // label columns is read from it before its answer is written there): with many labels the
    // start and the answer, nodes x labels floats each, are not held twice.
    WalkResult solve(const KnnGraph& graph, WalkProblem&& problem, const WalkOptions& options = {});
    // The same with the start and the answer in `x` (the problem's start unused): x empty, the
    // solve starts from the prior (or 0) and x becomes the answer, sparse past
    // options.dense_labels labels; else x is the start and the answer replaces it. Its
    // WalkResult::x stays empty.
    WalkResult solve(const KnnGraph& graph, const WalkProblem& problem, LabelColumns& x, const WalkOptions& options = {});
    const std::vector<vk::PassTiming>& timings() const { return timings_; }

    // For tests: the multigrid V-cycle z = B r on the GPU for `problem`'s operator (labels <=
    // kWalkMaxLabels columns, node-major), and the host hierarchy it was built from (that of the
    // last multigrid solve or cycle; empty if none).
    std::vector<float> cycle(const KnnGraph& graph, const WalkProblem& problem, const std::vector<float>& r,
                             const WalkOptions& options = {});
    const WalkHierarchy& hierarchy() const { return hierarchy_; }

private:
    WalkResult solve(const KnnGraph& graph, const WalkProblem& problem, std::vector<float> start,
                     const WalkOptions& options);
    // started: x holds the start; else the prior (or 0) starts and x, zero, takes the answer.
    WalkResult solve(const KnnGraph& graph, const WalkProblem& problem, LabelColumns& x, bool started,
                     const WalkOptions& options);
    // One level of the multigrid hierarchy on the device (level 0's operator is the graph's
    // rows and columns with edge_weights_; its r and z are the solve's r_ and z_).
    struct DeviceLevel {
        explicit DeviceLevel(vk::Context& ctx);
        vk::Buffer rows, columns, weights, diagonal, smoother, parent, child_rows, children, r, pre, z;
    };
    // Downloads the fine operator (after walk_rhs ran), builds the hierarchy and uploads it;
    // false when it did not coarsen (the solve then falls back to Jacobi).
    bool build_hierarchy(const KnnGraph& graph, const std::vector<int32_t>& seed, const std::vector<float>& gamma,
                         uint32_t width, const WalkOptions& options, WalkResult& out);
    // Records z = B r over levels [l, end) (level l's r and pre-smoothed z in place).
    void record_cycle(const KnnGraph& graph, uint32_t labels, float scale);

    vk::Context& ctx_;
    vk::CommandList cmd_;
    vk::Buffer seed_, gamma_, prior_, x_, b_, inv_diag_, coupling_, r_, z_, p_, ap_, partials_, scalars_, check_, check_partials_, best_x_, edge_weights_;
    std::vector<vk::PassTiming> timings_;
    WalkHierarchy hierarchy_;
    std::vector<DeviceLevel> levels_;
    std::vector<uint32_t> level_nodes_;
    vk::Buffer coarse_inverse_;
    // scalars_ then check_, copied there for the host where they are not mapped.
    static constexpr size_t kCheckAt = gpu::kWalkMaxLabels * sizeof(gpu::WalkScalars);
    vk::Buffer readback_;
};

}  // namespace pg::seg

#pragma once
// The random walker's multigrid hierarchy, built on the host (no Vulkan here, so the tests run it
// on the CPU): unsmoothed aggregation along strong connections, piecewise-constant prolongation
// P (a node takes its aggregate's value), Galerkin coarse operators P^T A P, levels until a few
// hundred nodes, and the coarsest operator's dense (pseudo-)inverse. The GPU applies it as a
// V-cycle preconditioner of the walk's conjugate gradient (random_walker.cpp).
#include <cstddef>
#include <cstdint>
#include <vector>

namespace pg::seg {

// A symmetric operator D - W over `size()` nodes: the off-diagonal weights w_ij >= 0 as CSR rows
// (both directions stored), the diagonal apart. A node with diagonal 0 takes no part (a seed, an
// isolated node without unary, a component that can hold no answer): its row is ignored and
// its neighbours' weights toward it must be 0.
struct WalkMatrix {
    std::vector<uint32_t> rows;     // size + 1 starts into columns / weights
    std::vector<uint32_t> columns;
    std::vector<float> weights;     // w_ij; the operator's entry is -w_ij
    std::vector<float> diagonal;
    uint32_t size() const { return uint32_t(diagonal.size()); }
};

struct HierarchyOptions {
    float strength = 0.25f;         // j is a strong neighbour of i if w_ij >= strength x i's largest weight
    uint32_t aggregate = 8;         // most nodes an aggregate starts with (stragglers may join one later)
    uint32_t coarsest = 400;        // stop coarsening at or below this many nodes (dense solve there)
    uint32_t max_levels = 12;
    float omega = 0.6f;             // the Jacobi smoother's step: z += omega / d (r - A z)
};

inline constexpr uint32_t kHierarchyNone = 0xFFFFFFFFu;
inline constexpr uint32_t kHierarchyMaxDense = 1024;  // most nodes of a coarsest level solved densely

struct WalkLevel {
    WalkMatrix matrix;
    std::vector<float> smoother;    // per node omega / diagonal, 0 for a node out of the system
    // Toward the next level (empty on the coarsest): per node its aggregate (kHierarchyNone when
    // out), and per aggregate its nodes as CSR (restriction sums them: no atomics needed).
    std::vector<uint32_t> parent;
    std::vector<uint32_t> child_rows, children;
};

struct WalkHierarchy {
    std::vector<WalkLevel> levels;  // [0] the operator it was built from
    std::vector<float> coarse_inverse;  // the coarsest operator's pseudo-inverse, dense row-major
                                        // (empty: coarsening stalled above kHierarchyMaxDense)
    uint32_t dropped = 0;               // fine nodes taken out by drop_unanchored
};

// Takes out of the system (diagonal 0) every component, along edges of positive weight, that
// holds no excess over its weights (no seed coupling, no unary term): its block is a bare graph
// Laplacian, singular, and has no answer to find; its nodes keep whatever they start from.
// Returns how many nodes it took out.
uint32_t drop_unanchored(WalkMatrix& a);

// Per node its aggregate (kHierarchyNone for a node out of the system); `count` the aggregates.
std::vector<uint32_t> aggregate_nodes(const WalkMatrix& a, const HierarchyOptions& options, uint32_t& count);

// P^T A P for the piecewise-constant P of `parent` (coarse nodes 0 .. coarse-1); a coarse node
// whose diagonal all but vanishes (a whole component without seed or unary) is left out.
WalkMatrix galerkin(const WalkMatrix& a, const std::vector<uint32_t>& parent, uint32_t coarse);

// The dense pseudo-inverse of a small operator (LDL^T; pivots that vanish are dropped, so a
// singular component gets no correction instead of a huge one), row-major.
std::vector<float> dense_pseudo_inverse(const WalkMatrix& a);

WalkHierarchy build_walk_hierarchy(WalkMatrix fine, const HierarchyOptions& options = {});

}  // namespace pg::seg

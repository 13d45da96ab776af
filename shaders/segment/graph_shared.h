// Layouts and constants shared by the graph decoder's C++ (engine/segment/knn_graph,
// random_walker) and its GLSL kernels (shaders/segment/graph_*, walk_*): one definition.
// Only vec4/uvec4-aligned members, so std430 and C++ agree byte for byte.
#ifndef PG_GRAPH_SHARED_H
#define PG_GRAPH_SHARED_H

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
namespace pg::seg::gpu {
using vec4 = glm::vec4;
using uvec4 = glm::uvec4;
using uint = uint32_t;
#define PG_GRAPH_CONST inline constexpr
#else
#define PG_GRAPH_CONST const
#endif

PG_GRAPH_CONST uint kGraphGroup = 256;
PG_GRAPH_CONST uint kGraphMaxK = 16;         // neighbours kept per node (the k option <= this)
PG_GRAPH_CONST uint kGraphNone = 0xFFFFFFFFu;  // an empty neighbour slot
PG_GRAPH_CONST uint kGraphMaxScan = 4096;      // kNN candidates one node looks at, at most
PG_GRAPH_CONST uint kGraphMaxShells = 4;     // most shells of cells a node short of k neighbours searches
PG_GRAPH_CONST uint kWalkMaxLabels = 16;     // label columns of one solve (more run as several)
PG_GRAPH_CONST uint kWalkVecs = kWalkMaxLabels / 4;  // most vec4s per node (a solve uses ceil(labels / 4))
PG_GRAPH_CONST int kWalkFree = -1;           // a node that is no seed

// graph_nodes: the domain's Gaussians gathered into node attributes.
struct GraphNodesPush {
    uvec4 size;  // x: nodes, y: SH words per Gaussian, z: 1 where the SH are fp16 pairs
};

// graph_cells, graph_knn: a uniform grid of cell side 1 / origin.w over the robust bounds.
struct GraphGridPush {
    vec4 origin;  // xyz: grid corner, w: 1 / cell side
    uvec4 dims;   // cells along x, y, z (a cell key packs x | y << bits.x | z << (bits.x + bits.y));
                  // w: shells of cells searched (beyond the first only while short of k)
    uvec4 bits;   // x, y: key bits of the x and y coordinates; z: nodes; w: k
    uvec4 pass;   // graph_knn: x 0 every node, the first shell only (listing the nodes short of k
                  // when dims.w > 1); x 1 the listed nodes, every shell
};

// graph_weights: affinity of an edge = colour x distance x normal x opacity terms.
struct GraphWeightsPush {
    vec4 beta;   // x: colour, y: normal, z: distance (in local spacings), w: opacity exponent
    uvec4 size;  // x: nodes, y: k
};

// graph_edge_keys, graph_row_counts, graph_rows: the symmetric adjacency W + W^T as CSR rows
// of columns and weights, each pair once.
struct GraphEdgesPush {
    uvec4 size;  // x: nodes, y: k, z: at most 2 n k entries, w: unused
};

// walk_*: the random walker's preconditioned conjugate gradient over up to kWalkMaxLabels
// columns (a node's values are ceil(labels / 4) vec4s, in arrays of kWalkVecs in registers).
struct WalkPush {
    uvec4 size;  // x: nodes, y: k, z: labels in use, w: workgroups of the node passes
    uvec4 mode;  // x: walk_apply 1 = also partial dots v . Av; walk_residual / walk_reduce 0 r.z,
                 // 1 alpha, 2 beta, 3 b.b / diag;
                 // y: the label of column 0 (seeds hold labels of all columns)
};

// walk_restrict, walk_coarsest, walk_prolong, walk_smooth: the multigrid V-cycle that
// preconditions the walk (engine/segment/walk_hierarchy): one weighted-Jacobi sweep before and
// after each coarse correction, the coarsest level by its dense pseudo-inverse.
struct WalkCyclePush {
    uvec4 size;   // x: nodes of this level, y: nodes of the next coarser one, z: labels in use,
                  // w: workgroups of this level's node pass (the partial dots' count)
    uvec4 mode;   // x: walk_smooth 1 = also the partial dots r . z (the finest level)
    vec4 scale;   // x: the coarse correction's scale (unsmoothed aggregation wants over-correction)
};

// forest_step: one round of the seeded maximum-spanning-forest relaxation. A node's state is
// (w, q): w the float bits of its widest path's weakest affinity to a seed, q the node just past
// that weakest edge (a seed: itself); (0, 0) means no seed reached yet. States compare as (w, q);
// positive floats order as their bits. The label is q's, resolved on the host from the widest
// nodes down: q is always strictly wider, so a label never outlives the path it came by, and
// the labelling is Kruskal's seeded maximum spanning forest's (exactly, for distinct weights).
PG_GRAPH_CONST float kForestSeedValue = 4.0f;  // above every pair's weight (both directions' affinities, each <= 1)
struct ForestPush {
    uvec4 size;  // x: nodes, y: k, z: this round's slot in the change counters, w: unused
};

// Per-label scalars of the solve (walk_reduce writes, walk_update / walk_direction read).
struct WalkScalars {
    vec4 value;  // x: r.z, y: alpha, z: beta, w: b.b / diag
};

#ifdef __cplusplus
}  // namespace pg::seg::gpu
#endif
#endif

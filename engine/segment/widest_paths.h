#pragma once
// The seeded widest-path labelling (seeded_forest.h) on the host: a max-heap flood from the
// seeds into the free nodes, O(E log E) over the free nodes' edges alone. When the walk has
// settled all but a few nodes, this is far cheaper than rounds of the GPU relaxation, each a
// pass over every node (on lavapipe 124 rounds of a 150 k graph took 0.35 s; the flood a few ms).
// No Vulkan here.
#include <cstdint>
#include <vector>

#include "engine/segment/host_adjacency.h"

namespace pg::seg {

struct WidestPaths {
    std::vector<int32_t> label;  // per node: the seed's label its widest path comes from; -1 unreached
    std::vector<float> width;    // that path's weakest affinity: 2 at seeds, 0 unreached
};

// seed: per node a label >= 0, or -1 for a free node. Edges of weight <= 0 are not paths. Widths
// are exact; where two seeds reach a node by paths of exactly equal width, either label may win.
WidestPaths widest_paths(const HostAdjacency& adjacency, const std::vector<int32_t>& seed);

}  // namespace pg::seg

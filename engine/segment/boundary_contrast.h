#pragma once
// How strongly a labelling's boundaries cut the graph: per label, the mean weight of the edges
// leaving it over the mean weight of the edges inside it. An answer cut where the graph is weak
// (a colour or normal change, a gap) scores near 0; one cut through an evenly weighted surface
// (by a background seed that lies on the object) scores near 1. No Vulkan here.
#include <cstdint>
#include <vector>

#include "engine/segment/host_adjacency.h"

namespace pg::seg {

// `label` per node (<= 0: none); the result has `labels` entries, index l for label l (entry 0
// and labels with no node or no inside edge: 0; a label with no leaving edge: 0).
std::vector<double> boundary_contrast(const HostAdjacency& graph, const std::vector<int32_t>& label, uint32_t labels);

}  // namespace pg::seg

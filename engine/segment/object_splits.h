#pragma once
// Where two objects' answers meet, the walk and the widest paths can split them differently. The
// walk cuts a thin object between its click and a large neighbour where the two pulls balance
// (the real guitar's stand, clicked near its foot, lost half of itself to the guitar it holds:
// stand 3D IoU 0.44), the widest paths at the weakest link on the way (where the stand touches
// the guitar: 0.90), but arbitrarily between look-alikes that share a surface (terraced houses,
// where the walk's midpoint is the better guess). So per pair of objects in contact, the widest
// paths' split replaces the walk's where it cuts far weaker edges. No Vulkan here.
#include <cstdint>
#include <vector>

#include "engine/segment/host_adjacency.h"

namespace pg::seg {

struct ObjectSplitOptions {
    // The widest paths' split between objects a and b stands where its contrast (the mean weight
    // of its a-b edges over the mean weight of the edges inside a and b) is below `clean` (a cut
    // between different things: 0.01 where the real guitar touches its stand; wrong splits of
    // look-alike houses and of a book's parts measured 0.05-0.25) and below `ratio` times the
    // walk's split's contrast (0 for either: never).
    float clean = 0.05f;
    float ratio = 0.5f;
    // ... and each of the two keeps at least this share of its nodes: a split that takes an object
    // away whole is a weak link next to its click (the widest paths' own failure), not a boundary.
    float keep = 0.5f;
};

// `label`: per node the walk's answer (> 0 an object, <= 0 none), changed in place; `seed`: per
// node a click's label (> 0 an object, 0 background) or -1. The widest paths run from the seeds
// through the nodes some object holds (the others are background to them). Per changed node
// `changed` (if given) is set to 1. Returns how many pairs of objects took the widest paths' split.
uint32_t settle_object_splits(const HostAdjacency& graph, const std::vector<int32_t>& seed, std::vector<int32_t>& label,
                              const ObjectSplitOptions& options, std::vector<uint8_t>* changed = nullptr);

}  // namespace pg::seg

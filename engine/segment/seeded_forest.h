#pragma once
// The graph decoder's other solver: every node takes the label of the seed it reaches by the
// widest path (the path whose weakest affinity is largest), i.e. the seeded maximum spanning
// forest's labelling (watershed on the graph). Unlike the random walk it has no bias towards
// large seed sets: one click holds its object against a whole background of seeds as long as
// the object's inside is better connected than its border. On the GPU as rounds of a
// relaxation (forest_step) until no node changes; a node no seed reaches stays unlabelled. With
// few free nodes (the walk settled the rest) it runs on the host instead (widest_paths.h).
#include <cstdint>
#include <vector>

#include "engine/segment/cancel.h"
#include "engine/segment/knn_graph.h"

namespace pg::seg {

struct ForestOptions {
    uint32_t max_rounds = 4000;
    uint32_t check_every = 32;   // rounds between the host's looks at the change counts
    float host_below = 0.25f;    // at most this share of the nodes free: the host's heap flood
                                 // (widest_paths.h) instead of the rounds (0: always the rounds)
    const std::atomic<bool>* cancel = nullptr;  // set: the solve stops (Cancelled) at its next look
};

struct ForestResult {
    std::vector<int32_t> label;  // per node, -1 where no seed is reached
    std::vector<float> width;    // per node: the widest path's weakest affinity (2 at seeds, 0 unreached)
    uint32_t rounds = 0;         // rounds until nothing changed (or max_rounds); 0 on the host
    bool converged = false;
    size_t free_nodes = 0;       // nodes without a seed: what the forest had to label
};

class SeededForest {
public:
    explicit SeededForest(vk::Context& ctx);
    // seed: per node a label or -1.
    ForestResult solve(const KnnGraph& graph, const std::vector<int32_t>& seed, const ForestOptions& options = {});
    const std::vector<vk::PassTiming>& timings() const { return timings_; }

private:
    vk::Context& ctx_;
    vk::CommandList cmd_;
    vk::Buffer seed_, state_[2], changed_;
    std::vector<vk::PassTiming> timings_;
};

}  // namespace pg::seg

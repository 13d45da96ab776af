#include "engine/segment/object_splits.h"

#include <algorithm>
#include <cstdint>
#include <map>
#include <utility>

#include "engine/segment/widest_paths.h"

namespace pg::seg {

namespace {

// The a-b edges' mean weight over the mean weight of the edges inside a and b, among `nodes`
// (all of a and b) labelled by `of`; 0 where a and b do not touch.
template <class LabelOf>
double pair_contrast(const HostAdjacency& g, const std::vector<uint32_t>& nodes, int32_t a, int32_t b, LabelOf of) {
    double cut = 0, inside = 0, cuts = 0, insides = 0;
    for (uint32_t i : nodes) {
        const int32_t li = of(i);
        for (uint32_t e = g.rows[i]; e < g.rows[i + 1]; ++e) {
            const int32_t lj = of(g.columns[e]);
            if (lj != a && lj != b) continue;
            if (lj == li) inside += g.weights[e], insides += 1;
            else cut += g.weights[e], cuts += 1;
        }
    }
    return cuts > 0 && inside > 0 ? (cut / cuts) / (inside / insides) : 0.0;
}

}  // namespace

uint32_t settle_object_splits(const HostAdjacency& graph, const std::vector<int32_t>& seed, std::vector<int32_t>& label,
                              const ObjectSplitOptions& options, std::vector<uint8_t>* changed) {
    if (!(options.ratio > 0) || !(options.clean > 0)) return 0;
    const uint32_t n = graph.nodes();
    // The widest paths from the clicks, through what the objects hold: the rest is background.
    std::vector<int32_t> start(n);
    int32_t one = 0;
    bool several = false;
    for (uint32_t i = 0; i < n; ++i) {
        start[i] = label[i] > 0 ? seed[i] : 0;
        if (label[i] > 0) several |= one > 0 && label[i] != one, one = label[i];
    }
    if (!several) return 0;
    const WidestPaths paths = widest_paths(graph, start);

    // Nodes the two answers give to different objects, per pair of objects.
    std::map<std::pair<int32_t, int32_t>, std::vector<uint32_t>> disputed;
    for (uint32_t i = 0; i < n; ++i)
        if (const int32_t w = label[i], f = paths.label[i]; w > 0 && f > 0 && w != f)
            disputed[{std::min(w, f), std::max(w, f)}].push_back(i);
    if (disputed.empty()) return 0;
    std::map<int32_t, std::vector<uint32_t>> members;  // the walk's, for the objects in a dispute
    for (const auto& [pair, nodes] : disputed) members[pair.first], members[pair.second];
    for (uint32_t i = 0; i < n; ++i)
        if (auto it = members.find(label[i]); it != members.end()) it->second.push_back(i);

    const std::vector<int32_t> walk = label;  // every pair is judged against the walk's answer
    std::vector<uint8_t> moved(n, 0);
    uint32_t taken = 0;
    for (const auto& [pair, nodes] : disputed) {
        const auto [a, b] = pair;
        std::vector<uint32_t> both = members[a];
        both.insert(both.end(), members[b].begin(), members[b].end());
        for (uint32_t i : nodes) moved[i] = 1;
        auto by_walk = [&](uint32_t i) { return walk[i]; };
        auto by_paths = [&](uint32_t i) { return moved[i] ? paths.label[i] : walk[i]; };
        const double before = pair_contrast(graph, both, a, b, by_walk);
        const double after = pair_contrast(graph, both, a, b, by_paths);
        // The disputed nodes change hands between a and b: sizes after the move.
        int64_t to_a = 0;
        for (uint32_t i : nodes) to_a += paths.label[i] == a ? 1 : -1;
        const double a_after = double(int64_t(members[a].size()) + to_a), b_after = double(int64_t(members[b].size()) - to_a);
        const bool keeps = a_after >= double(options.keep) * double(members[a].size()) &&
                           b_after >= double(options.keep) * double(members[b].size());
        const bool take = before > 0 && after < double(options.ratio) * before && after < double(options.clean) && keeps;
        for (uint32_t i : nodes) {
            moved[i] = 0;
            if (!take) continue;
            label[i] = paths.label[i];
            if (changed) (*changed)[i] = 1;
        }
        taken += take;
    }
    return taken;
}

}  // namespace pg::seg

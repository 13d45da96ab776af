#include "engine/segment/object_splits.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <map>
#include <utility>

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

// The label each node's widest path from the seeds brings (-1: none), widths bucketed in 64ths
// of a binary order of magnitude (from the float's exponent and top mantissa bits) and flooded
// widest bucket first. With a heap's exact order (widest_paths.h) the whole split took 70 ms on
// the real guitar (90 k claimed nodes), with buckets 28; a split only needs to tell a contact
// 100x weaker than the insides.
std::vector<int32_t> bucketed_widest_labels(const HostAdjacency& g, const std::vector<int32_t>& seed) {
    constexpr int kSteps = 64, kBuckets = kSteps * 40 + 1;  // down to 2^-40; weaker edges share the last
    auto bucket = [](float w) {
        uint32_t bits;
        std::memcpy(&bits, &w, sizeof bits);
        const int exponent = int((bits >> 23) & 0xFFu) - 127, step = int((bits >> 17) & 63u);
        return std::clamp(-(kSteps * exponent + step), 0, kBuckets - 1);
    };
    const uint32_t n = g.nodes();
    std::vector<int32_t> label(n, -1);
    std::vector<int16_t> best(n, int16_t(kBuckets));
    std::vector<uint8_t> done(n, 0);
    std::vector<std::vector<uint32_t>> queue(kBuckets);
    auto reach = [&](uint32_t i, int from) {
        for (uint32_t e = g.rows[i]; e < g.rows[i + 1]; ++e) {
            const uint32_t j = g.columns[e];
            if (seed[j] >= 0 || done[j] || !(g.weights[e] > 0)) continue;
            if (const int b = std::max(from, bucket(g.weights[e])); b < best[j]) best[j] = int16_t(b), label[j] = label[i], queue[size_t(b)].push_back(j);
        }
    };
    for (uint32_t i = 0; i < n; ++i)
        if (seed[i] >= 0) label[i] = seed[i], done[i] = 1;
    for (uint32_t i = 0; i < n; ++i)
        if (seed[i] >= 0) reach(i, 0);
    for (int b = 0; b < kBuckets; ++b)
        for (size_t q = 0; q < queue[size_t(b)].size(); ++q) {  // grows while it is read
            const uint32_t i = queue[size_t(b)][q];
            if (done[i] || best[i] != b) continue;
            done[i] = 1;
            reach(i, b);
        }
    return label;
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
    bool touch = false;  // two objects' answers share an edge
    for (uint32_t i = 0; i < n && !touch; ++i)
        if (label[i] > 0)
            for (uint32_t e = graph.rows[i]; e < graph.rows[i + 1] && !touch; ++e)
                touch = label[graph.columns[e]] > 0 && label[graph.columns[e]] != label[i];
    if (!touch) return 0;
    const std::vector<int32_t> paths = bucketed_widest_labels(graph, start);

    // Nodes the two answers give to different objects, per pair of objects.
    std::map<std::pair<int32_t, int32_t>, std::vector<uint32_t>> disputed;
    for (uint32_t i = 0; i < n; ++i)
        if (const int32_t w = label[i], f = paths[i]; w > 0 && f > 0 && w != f)
            disputed[{std::min(w, f), std::max(w, f)}].push_back(i);
    if (disputed.empty()) return 0;
    std::map<int32_t, std::vector<uint32_t>> members;  // the walk's, for the objects in a dispute
    for (const auto& [pair, nodes] : disputed) members[pair.first], members[pair.second];
    for (uint32_t i = 0; i < n; ++i)
        if (auto it = members.find(label[i]); it != members.end()) it->second.push_back(i);

    // Every pair is judged against the walk's answer: the moves are made once all are judged
    // (the disputed sets are disjoint).
    const std::vector<int32_t>& walk = label;
    std::vector<uint8_t> moved(n, 0);
    std::vector<const std::vector<uint32_t>*> take_nodes;
    uint32_t taken = 0;
    for (const auto& [pair, nodes] : disputed) {
        const auto [a, b] = pair;
        std::vector<uint32_t> both = members[a];
        both.insert(both.end(), members[b].begin(), members[b].end());
        for (uint32_t i : nodes) moved[i] = 1;
        auto by_walk = [&](uint32_t i) { return walk[i]; };
        auto by_paths = [&](uint32_t i) { return moved[i] ? paths[i] : walk[i]; };
        const double before = pair_contrast(graph, both, a, b, by_walk);
        const double after = pair_contrast(graph, both, a, b, by_paths);
        // The disputed nodes change hands between a and b: sizes after the move.
        int64_t to_a = 0;
        for (uint32_t i : nodes) to_a += paths[i] == a ? 1 : -1;
        const double a_after = double(int64_t(members[a].size()) + to_a), b_after = double(int64_t(members[b].size()) - to_a);
        const bool keeps = a_after >= double(options.keep) * double(members[a].size()) &&
                           b_after >= double(options.keep) * double(members[b].size());
        const bool take = before > 0 && after < double(options.ratio) * before && after < double(options.clean) && keeps;
        for (uint32_t i : nodes) moved[i] = 0;
        if (take) take_nodes.push_back(&nodes), ++taken;
    }
    for (const auto* nodes : take_nodes)
        for (uint32_t i : *nodes) {
            label[i] = paths[i];
            if (changed) (*changed)[i] = 1;
        }
    return taken;
}

}  // namespace pg::seg

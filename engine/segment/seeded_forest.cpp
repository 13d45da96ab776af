#include "engine/segment/seeded_forest.h"

#include <algorithm>
#include <cstring>
#include <string>

#include "dataset/error.h"
#include "engine/segment/widest_paths.h"
#include "shaders/segment/graph_shared.h"

namespace pg::seg {

SeededForest::SeededForest(vk::Context& ctx) : ctx_(ctx), cmd_(ctx) {
    for (auto* b : {&seed_, &state_[0], &state_[1], &changed_}) *b = vk::Buffer(ctx, 16, vk::MemoryUse::Device, "seeded forest");
}

ForestResult SeededForest::solve(const KnnGraph& graph, const std::vector<int32_t>& seed, const ForestOptions& o) {
    const uint32_t n = graph.nodes();
    if (seed.size() != n)
        throw data::InputError("seeded forest seeds", "has " + std::to_string(seed.size()) + " values, expected " +
                                                          std::to_string(n));
    if (std::any_of(seed.begin(), seed.end(), [](int32_t l) { return l < -1; }))
        throw data::InputError("seeded forest seeds", "hold a label out of range");
    ForestResult out;
    timings_.clear();
    out.free_nodes = size_t(std::count(seed.begin(), seed.end(), -1));
    if (n > 0 && double(out.free_nodes) <= double(o.host_below) * n) {
        auto paths = widest_paths(graph.host_adjacency(), seed);
        out.label = std::move(paths.label);
        out.width = std::move(paths.width);
        out.converged = true;
        return out;
    }
    // (width bits, node past the weakest edge) per node: a seed is (kForestSeedValue, itself).
    uint32_t seed_bits;
    std::memcpy(&seed_bits, &gpu::kForestSeedValue, 4);
    std::vector<glm::uvec2> state(n, glm::uvec2(0));
    for (uint32_t i = 0; i < n; ++i)
        if (seed[i] >= 0) state[i] = {seed_bits, i};
    if (n > 0) {
        const uint32_t check = std::max(1u, o.check_every);
        seed_.ensure(uint64_t(n) * 4);
        for (auto& s : state_) s.ensure(uint64_t(n) * 8);
        changed_.ensure(uint64_t(check) * 4);
        vk::upload(ctx_, seed_, seed.data(), uint64_t(n) * 4);
        vk::upload(ctx_, state_[0], state.data(), uint64_t(n) * 8);
        const std::vector<uint32_t> zeros(check, 0);
        uint32_t current = 0;  // the buffer holding the latest state
        while (!out.converged && out.rounds < o.max_rounds) {
            vk::upload(ctx_, changed_, zeros.data(), uint64_t(check) * 4);
            const uint32_t rounds = std::min(check, o.max_rounds - out.rounds);
            cmd_.begin_pass("forest rounds");
            for (uint32_t r = 0; r < rounds; ++r) {
                gpu::ForestPush push{{n, graph.k(), r, 0}};
                cmd_.dispatch("segment/forest_step",
                              {graph.rows(), graph.columns(), graph.adjacency_weights(), seed_,
                               state_[current], state_[current ^ 1], changed_},
                              push, vk::ceil_div(n, gpu::kGraphGroup));
                current ^= 1;
            }
            cmd_.end_pass();
            cmd_.submit_and_wait();
            for (auto& t : cmd_.timings()) timings_.push_back(t);
            stop_if_cancelled(o.cancel);
            auto changed = vk::download_vector<uint32_t>(ctx_, changed_, rounds);
            for (uint32_t r = 0; r < rounds && !out.converged; ++r) {
                ++out.rounds;
                out.converged = changed[r] == 0;
            }
        }
        state = vk::download_vector<glm::uvec2>(ctx_, state_[current], n);
    }
    // Labels from the widest nodes down: the node past a node's weakest edge is strictly wider,
    // so its label is known by then.
    out.label.assign(n, -1);
    out.width.assign(n, 0.0f);
    std::vector<uint32_t> order;
    for (uint32_t i = 0; i < n; ++i)
        if (state[i].x != 0) {
            std::memcpy(&out.width[i], &state[i].x, 4);
            order.push_back(i);
        }
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return state[a].x > state[b].x; });
    for (uint32_t i : order) out.label[i] = seed[i] >= 0 ? seed[i] : out.label[state[i].y];
    return out;
}

}  // namespace pg::seg

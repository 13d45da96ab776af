#include "engine/segment/random_walker.h"

#include <algorithm>
#include <cmath>

#include "dataset/error.h"
#include "shaders/segment/graph_shared.h"

namespace pg::seg {

RandomWalker::RandomWalker(vk::Context& ctx) : ctx_(ctx), cmd_(ctx) {
    for (auto* b : {&seed_, &gamma_, &prior_, &x_, &b_, &inv_diag_, &r_, &z_, &p_, &ap_, &partials_, &scalars_, &edge_columns_, &edge_weights_})
        *b = vk::Buffer(ctx, 16, vk::MemoryUse::Device, "random walker");
}

WalkResult RandomWalker::solve(const KnnGraph& graph, const WalkProblem& pr, const WalkOptions& o) {
    const uint32_t n = graph.nodes(), total = pr.labels;
    auto sized = [&](size_t got, size_t want, const char* what) {
        if (got != 0 && got != want)
            throw data::InputError(std::string("random walker ") + what,
                                   "has " + std::to_string(got) + " values, expected " + std::to_string(want));
    };
    sized(pr.seed.size(), n, "seeds");
    if (pr.seed.empty() && n) throw data::InputError("random walker seeds", "are missing");
    sized(pr.gamma.size(), n, "unary strengths");
    sized(pr.prior.size(), size_t(n) * total, "priors");
    sized(pr.start.size(), size_t(n) * total, "starting point");
    for (int32_t s : pr.seed)
        if (s < -1 || s >= int32_t(total)) throw data::InputError("random walker seeds", "hold a label out of range");
    WalkResult out;
    out.x.assign(size_t(n) * total, 0.0f);
    if (n == 0 || total == 0) return out;

    const uint32_t node_groups = vk::ceil_div(n, gpu::kGraphGroup);
    std::vector<float> gamma = pr.gamma.empty() ? std::vector<float>(n, 0.0f) : pr.gamma;
    seed_.ensure(uint64_t(n) * 4);
    gamma_.ensure(uint64_t(n) * 4);
    vk::upload(ctx_, seed_, pr.seed.data(), uint64_t(n) * 4);
    vk::upload(ctx_, gamma_, gamma.data(), uint64_t(n) * 4);
    inv_diag_.ensure(uint64_t(n) * 4);
    edge_columns_.ensure(2ull * n * graph.k() * 4);
    edge_weights_.ensure(2ull * n * graph.k() * 4);
    const uint32_t most = std::min(total, gpu::kWalkMaxLabels);
    const uint32_t most_width = (most + 3) / 4 * 4;
    for (auto* b : {&prior_, &x_, &b_, &r_, &z_, &p_, &ap_}) b->ensure(uint64_t(n) * most_width * 4);
    partials_.ensure(uint64_t(node_groups) * gpu::kWalkMaxLabels * 4);
    scalars_.ensure(uint64_t(gpu::kWalkMaxLabels) * sizeof(gpu::WalkScalars));
    timings_.clear();

    for (uint32_t base = 0; base < total; base += gpu::kWalkMaxLabels) {
        const uint32_t labels = std::min(gpu::kWalkMaxLabels, total - base);
        // This solve's columns, `width` per node (the labels rounded up to vec4s; the rest stay 0):
        // the passes' memory traffic follows the labels in use.
        const uint32_t width = (labels + 3) / 4 * 4;
        const uint64_t bytes = uint64_t(n) * width * 4;
        auto columns = [&](const std::vector<float>& from) {
            std::vector<float> c(size_t(n) * width, 0.0f);
            if (!from.empty())
                for (uint32_t i = 0; i < n; ++i)
                    for (uint32_t l = 0; l < labels; ++l) c[size_t(i) * width + l] = from[size_t(i) * total + base + l];
            return c;
        };
        auto prior = columns(pr.prior);
        vk::upload(ctx_, prior_, prior.data(), bytes);
        auto x0 = pr.start.empty() ? prior : columns(pr.start);
        vk::upload(ctx_, x_, x0.data(), bytes);

        gpu::WalkPush push[4];
        for (uint32_t mode = 0; mode < 4; ++mode) push[mode] = {{n, graph.k(), labels, node_groups}, {mode, base, 0, 0}};
        const auto& rows = graph.rows();
        const auto& entries = graph.entries();
        const auto& nbr = graph.neighbour_buffer();
        const auto& w = graph.weight_buffer();
        const auto& deg = graph.degree_buffer();
        const uint32_t reduce_groups = width / 4;
        cmd_.begin_pass("walk start");
        cmd_.dispatch("segment/walk_rhs", {rows, entries, nbr, w, deg, seed_, gamma_, prior_, x_, b_, inv_diag_},
                      push[0], node_groups);
        cmd_.dispatch("segment/walk_edges", {entries, nbr, w, seed_, rows, edge_columns_, edge_weights_}, push[0],
                      vk::ceil_div(2ull * n * graph.k(), gpu::kGraphGroup));
        cmd_.dispatch("segment/walk_apply", {rows, edge_columns_, edge_weights_, deg, seed_, gamma_, x_, ap_, partials_}, push[0], node_groups);
        cmd_.dispatch("segment/walk_residual", {b_, ap_, inv_diag_, r_, z_, p_, partials_}, push[3], node_groups);
        cmd_.dispatch("segment/walk_reduce", {partials_, scalars_}, push[3], reduce_groups);
        cmd_.dispatch("segment/walk_residual", {b_, ap_, inv_diag_, r_, z_, p_, partials_}, push[0], node_groups);
        cmd_.dispatch("segment/walk_reduce", {partials_, scalars_}, push[0], reduce_groups);
        cmd_.end_pass();

        uint32_t it = 0;
        double residual = 0;
        for (;;) {
            cmd_.submit_and_wait();
            for (auto& t : cmd_.timings()) timings_.push_back(t);
            auto s = vk::download_vector<gpu::WalkScalars>(ctx_, scalars_, labels);
            residual = 0;
            for (auto& v : s)
                residual = std::max(residual, v.value.w > 0 ? std::sqrt(std::max(0.0f, v.value.x) / v.value.w) : 0.0);
            if (residual <= o.tolerance || it >= o.max_iterations) break;
            cmd_.begin_pass("walk iterations");
            for (uint32_t c = 0; c < o.check_every && it < o.max_iterations; ++c, ++it) {
                cmd_.dispatch("segment/walk_apply", {rows, edge_columns_, edge_weights_, deg, seed_, gamma_, p_, ap_, partials_}, push[1],
                              node_groups);
                cmd_.dispatch("segment/walk_reduce", {partials_, scalars_}, push[1], reduce_groups);
                cmd_.dispatch("segment/walk_update", {scalars_, p_, ap_, inv_diag_, x_, r_, z_, partials_}, push[0],
                              node_groups);
                cmd_.dispatch("segment/walk_reduce", {partials_, scalars_}, push[2], reduce_groups);
                cmd_.dispatch("segment/walk_direction", {scalars_, z_, p_}, push[0], node_groups);
            }
            cmd_.end_pass();
        }
        out.iterations = std::max(out.iterations, it);
        out.residual = std::max(out.residual, residual);
        auto x = vk::download_vector<float>(ctx_, x_, size_t(n) * width);
        for (uint32_t i = 0; i < n; ++i)
            for (uint32_t l = 0; l < labels; ++l) out.x[size_t(i) * total + base + l] = x[size_t(i) * width + l];
    }
    return out;
}

}  // namespace pg::seg

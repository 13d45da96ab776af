#include "engine/segment/random_walker.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <type_traits>

#include "dataset/error.h"
#include "shaders/segment/graph_shared.h"

namespace pg::seg {

namespace {

// Free nodes' values outside [-slack, 1 + slack] or NaN, clamped into [0, 1] (NaN to 0) when the
// columns may change.
template <class Columns>
uint64_t visit_outside(Columns& columns, const std::vector<int32_t>& seed, uint32_t width, uint32_t labels, float slack) {
    uint64_t outside = 0;
    for (size_t i = 0; i < seed.size(); ++i) {
        if (seed[i] != gpu::kWalkFree) continue;
        for (uint32_t l = 0; l < labels; ++l) {
            auto& v = columns[i * width + l];
            if (v >= -slack && v <= 1.0f + slack) continue;  // false for NaN
            ++outside;
            if constexpr (!std::is_const_v<Columns>) v = std::isnan(v) ? 0.0f : std::clamp(v, 0.0f, 1.0f);
        }
    }
    return outside;
}

}  // namespace

uint64_t walk_values_outside(const std::vector<float>& columns, const std::vector<int32_t>& seed, uint32_t width,
                             uint32_t labels, float slack) {
    return visit_outside(columns, seed, width, labels, slack);
}

uint64_t clamp_walk_values(std::vector<float>& columns, const std::vector<int32_t>& seed, uint32_t width,
                           uint32_t labels, float slack) {
    return visit_outside(columns, seed, width, labels, slack);
}

namespace {

// Into `to` when `cmd` runs (one submission for all of a hierarchy's arrays).
template <class T>
void put(vk::CommandList& cmd, vk::Buffer& to, const std::vector<T>& from) {
    to.ensure(std::max<uint64_t>(16, from.size() * sizeof(T)));
    cmd.upload(to, from.data(), from.size() * sizeof(T));
}

// A node pass built for this solve's vec4s of label columns per node (shaders/CMakeLists.txt).
std::string walk_kernel(const char* name, uint32_t labels) {
    return std::string(name) + "_v" + std::to_string((std::min(labels, gpu::kWalkMaxLabels) + 3) / 4);
}

}  // namespace

RandomWalker::RandomWalker(vk::Context& ctx)
    : ctx_(ctx), cmd_(ctx), readback_(ctx, 2 * kCheckAt, vk::MemoryUse::Readback, "random walker scalars") {
    for (auto* b : {&seed_, &gamma_, &prior_, &x_, &b_, &inv_diag_, &coupling_, &r_, &z_, &p_, &ap_, &partials_, &scalars_, &check_, &check_partials_, &best_x_, &edge_weights_, &coarse_inverse_})
        *b = vk::Buffer(ctx, 16, vk::MemoryUse::Device, "random walker");
}

RandomWalker::DeviceLevel::DeviceLevel(vk::Context& ctx) {
    for (auto* b : {&rows, &columns, &weights, &diagonal, &smoother, &parent, &child_rows, &children, &r, &pre, &z})
        *b = vk::Buffer(ctx, 16, vk::MemoryUse::Device, "random walker level");
}

bool RandomWalker::build_hierarchy(const KnnGraph& graph, const std::vector<int32_t>& seed, const std::vector<float>& gamma,
                                   uint32_t width, const WalkOptions& o, WalkResult& out) {
    const auto t0 = std::chrono::steady_clock::now();
    const uint32_t n = graph.nodes();
    // The fine operator as walk_apply sees it, from the graph's host copy (downloaded once per
    // graph, not once per click): walk_rhs's columns and edge weights (0 toward seeds), degree +
    // gamma on the diagonal; a seed's row is out of the system.
    const HostAdjacency& adjacency = graph.host_adjacency();
    // In the last hierarchy's finest level's memory (fresh pages fault on first touch: ~5 ms here).
    WalkMatrix fine = hierarchy_.levels.empty() ? WalkMatrix{} : std::move(hierarchy_.levels[0].matrix);
    fine.rows.assign(adjacency.rows.begin(), adjacency.rows.end());
    fine.columns.assign(adjacency.columns.begin(), adjacency.columns.end());
    fine.weights.assign(adjacency.weights.begin(), adjacency.weights.end());
    for (size_t s = 0; s < fine.columns.size(); ++s)
        if (seed[fine.columns[s]] != gpu::kWalkFree) fine.weights[s] = 0.0f;
    fine.diagonal.assign(adjacency.degree.begin(), adjacency.degree.end());
    for (uint32_t i = 0; i < n; ++i) {
        const float d = fine.diagonal[i] + gamma[i];
        fine.diagonal[i] = seed[i] == gpu::kWalkFree && d > 0.0f ? d : 0.0f;
    }
    hierarchy_ = build_walk_hierarchy(std::move(fine), o.hierarchy);
    const WalkHierarchy& h = hierarchy_;
    out.hierarchy_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (h.levels.size() < 2 || h.coarse_inverse.empty()) return false;
    const size_t count = h.levels.size();
    while (levels_.size() < count) levels_.emplace_back(ctx_);
    level_nodes_.assign(count, 0);
    for (size_t l = 0; l < count; ++l) {
        const WalkLevel& from = h.levels[l];
        DeviceLevel& to = levels_[l];
        level_nodes_[l] = from.matrix.size();
        if (l > 0) {
            // Level 0's operator and vectors are the solve's own buffers.
            put(cmd_, to.rows, from.matrix.rows);
            put(cmd_, to.columns, from.matrix.columns);
            put(cmd_, to.weights, from.matrix.weights);
            to.r.ensure(uint64_t(level_nodes_[l]) * width * 4);
            to.z.ensure(uint64_t(level_nodes_[l]) * width * 4);
        }
        put(cmd_, to.diagonal, from.matrix.diagonal);
        put(cmd_, to.smoother, from.smoother);
        to.pre.ensure(uint64_t(level_nodes_[l]) * width * 4);
        if (l + 1 < count) {
            put(cmd_, to.parent, from.parent);
            put(cmd_, to.child_rows, from.child_rows);
            put(cmd_, to.children, from.children);
        }
    }
    put(cmd_, coarse_inverse_, h.coarse_inverse);
    out.levels = uint32_t(count);
    out.hierarchy_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return true;
}

std::vector<float> RandomWalker::cycle(const KnnGraph& graph, const WalkProblem& pr, const std::vector<float>& r,
                                      const WalkOptions& o) {
    const uint32_t n = graph.nodes(), labels = pr.labels, width = (labels + 3) / 4 * 4;
    if (labels == 0 || labels > gpu::kWalkMaxLabels || pr.seed.size() != n || r.size() != size_t(n) * labels)
        throw data::InputError("random walker cycle", "expects 1 to 16 labels, a seed and r per node");
    const std::vector<float> gamma = pr.gamma.empty() ? std::vector<float>(n, 0.0f) : pr.gamma;
    // walk_rhs gives the solve's edge weights (its b, x and diagonals go unused here).
    seed_.ensure(uint64_t(n) * 4);
    gamma_.ensure(uint64_t(n) * 4);
    cmd_.upload(seed_, pr.seed.data(), uint64_t(n) * 4);
    cmd_.upload(gamma_, gamma.data(), uint64_t(n) * 4);
    for (auto* b : {&prior_, &x_, &b_}) b->ensure(uint64_t(n) * width * 4);
    cmd_.fill(prior_, 0, 0, uint64_t(n) * width * 4);
    for (auto* b : {&inv_diag_, &coupling_}) b->ensure(uint64_t(n) * 4);
    edge_weights_.ensure(2ull * n * graph.k() * 4);
    const gpu::WalkPush push{{n, graph.k(), labels, vk::ceil_div(n, gpu::kGraphGroup)}, {0, 0, 0, 0}};
    cmd_.begin_pass("walk edges");
    cmd_.dispatch(walk_kernel("segment/walk_rhs", labels),
                  {graph.rows(), graph.columns(), graph.adjacency_weights(), graph.degree_buffer(), seed_, gamma_, prior_, x_, b_,
                   inv_diag_, coupling_, edge_weights_},
                  push, push.size.w);
    cmd_.end_pass();
    cmd_.submit_and_wait();
    WalkResult unused;
    if (!build_hierarchy(graph, pr.seed, gamma, width, o, unused))
        throw data::InputError("random walker cycle", "the graph did not coarsen");
    // r in this solve's layout; walk_residual with A x = 0 gives the cycle its r and level 0's
    // pre-smoothing, as in a solve.
    std::vector<float> columns(size_t(n) * width, 0.0f), zero(size_t(n) * width, 0.0f);
    for (uint32_t i = 0; i < n; ++i)
        for (uint32_t l = 0; l < labels; ++l) columns[size_t(i) * width + l] = r[size_t(i) * labels + l];
    for (auto* b : {&b_, &ap_, &r_, &z_, &p_}) b->ensure(uint64_t(n) * width * 4);
    partials_.ensure(uint64_t(push.size.w) * gpu::kWalkMaxLabels * 4);
    cmd_.upload(b_, columns.data(), columns.size() * 4);
    cmd_.upload(ap_, zero.data(), zero.size() * 4);
    cmd_.begin_pass("walk cycle");
    cmd_.dispatch(walk_kernel("segment/walk_residual", labels), {b_, ap_, levels_[0].smoother, r_, levels_[0].pre, p_, partials_}, push,
                  push.size.w);
    record_cycle(graph, labels, o.coarse_scale);
    cmd_.end_pass();
    cmd_.submit_and_wait();
    auto z = vk::download_vector<float>(ctx_, z_, size_t(n) * width);
    std::vector<float> out(size_t(n) * labels);
    for (uint32_t i = 0; i < n; ++i)
        for (uint32_t l = 0; l < labels; ++l) out[size_t(i) * labels + l] = z[size_t(i) * width + l];
    return out;
}

void RandomWalker::record_cycle(const KnnGraph& graph, uint32_t labels, float scale) {
    const uint32_t count = uint32_t(level_nodes_.size());
    auto rows = [&](uint32_t l) -> const vk::Buffer& { return l == 0 ? graph.rows() : levels_[l].rows; };
    auto columns = [&](uint32_t l) -> const vk::Buffer& { return l == 0 ? graph.columns() : levels_[l].columns; };
    auto weights = [&](uint32_t l) -> const vk::Buffer& { return l == 0 ? edge_weights_ : levels_[l].weights; };
    auto r = [&](uint32_t l) -> const vk::Buffer& { return l == 0 ? r_ : levels_[l].r; };
    auto z = [&](uint32_t l) -> const vk::Buffer& { return l == 0 ? z_ : levels_[l].z; };
    auto push = [&](uint32_t l, uint32_t partials) {
        const uint32_t next = l + 1 < count ? level_nodes_[l + 1] : 0;
        return gpu::WalkCyclePush{{level_nodes_[l], next, labels, vk::ceil_div(level_nodes_[l], gpu::kGraphGroup)},
                                  {partials, 0, 0, 0},
                                  {scale, 0, 0, 0}};
    };
    // Down: level l's residual after its pre-smoothing, summed per aggregate, is level l + 1's
    // right-hand side (level 0's pre-smoothing is walk_update's / walk_residual's z).
    for (uint32_t l = 0; l + 1 < count; ++l) {
        const DeviceLevel& at = levels_[l];
        cmd_.dispatch(walk_kernel("segment/walk_restrict", labels),
                      {rows(l), columns(l), weights(l), at.diagonal, at.child_rows, at.children, r(l), at.pre,
                       levels_[l + 1].smoother, r(l + 1), levels_[l + 1].pre},
                      push(l, 0), vk::ceil_div(level_nodes_[l + 1], gpu::kGraphGroup));
    }
    cmd_.dispatch(walk_kernel("segment/walk_coarsest", labels), {coarse_inverse_, r(count - 1), z(count - 1)}, push(count - 1, 0),
                  vk::ceil_div(level_nodes_[count - 1], 64));
    // Up: the coarse correction, then the post-smoothing sweep.
    for (uint32_t l = count - 1; l-- > 0;) {
        const DeviceLevel& at = levels_[l];
        const uint32_t groups = vk::ceil_div(level_nodes_[l], gpu::kGraphGroup);
        cmd_.dispatch(walk_kernel("segment/walk_prolong", labels), {at.parent, z(l + 1), at.pre}, push(l, 0), groups);
        cmd_.dispatch(walk_kernel("segment/walk_smooth", labels), {rows(l), columns(l), weights(l), at.diagonal, at.smoother, r(l), at.pre, z(l), partials_},
                      push(l, l == 0 ? 1 : 0), groups);
    }
}

WalkResult RandomWalker::solve(const KnnGraph& graph, const WalkProblem& pr, const WalkOptions& o) {
    return solve(graph, pr, pr.start, o);
}

WalkResult RandomWalker::solve(const KnnGraph& graph, WalkProblem&& pr, const WalkOptions& o) {
    std::vector<float> start = std::move(pr.start);
    pr.start.clear();
    return solve(graph, pr, std::move(start), o);
}

WalkResult RandomWalker::solve(const KnnGraph& graph, const WalkProblem& pr, std::vector<float> start,
                               const WalkOptions& o) {
    const size_t want = size_t(graph.nodes()) * pr.labels;
    if (!start.empty() && start.size() != want)
        throw data::InputError("random walker starting point",
                               "has " + std::to_string(start.size()) + " values, expected " + std::to_string(want));
    const bool started = !start.empty();
    LabelColumns x = started ? LabelColumns::dense(std::move(start), pr.labels)
                             : LabelColumns(graph.nodes(), pr.labels, false);
    WalkResult out = solve(graph, pr, x, started, o);
    out.x = x.take_dense();
    return out;
}

WalkResult RandomWalker::solve(const KnnGraph& graph, const WalkProblem& pr, LabelColumns& x, const WalkOptions& o) {
    const bool started = !x.empty();
    if (!started) x = LabelColumns(graph.nodes(), pr.labels, pr.labels > o.dense_labels);
    return solve(graph, pr, x, started, o);
}

WalkResult RandomWalker::solve(const KnnGraph& graph, const WalkProblem& pr, LabelColumns& x, bool started,
                               const WalkOptions& o) {
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
    if (x.nodes() != n || x.labels() != total)
        throw data::InputError("random walker starting point", "holds " + std::to_string(x.nodes()) + " nodes x " +
                                                                   std::to_string(x.labels()) + " labels, expected " +
                                                                   std::to_string(n) + " x " + std::to_string(total));
    for (int32_t s : pr.seed)
        if (s < -1 || s >= int32_t(total)) throw data::InputError("random walker seeds", "hold a label out of range");
    WalkResult out;
    if (n == 0 || total == 0) return out;
    // The answer takes the start's place in x, column batch by column batch (dense: a batch's
    // columns are read before its answer overwrites them). A sparse node's few values are shared
    // by all its columns, so there the answer is gathered apart and replaces the start at the end.
    LabelColumns apart;
    if (started && x.sparse()) apart = LabelColumns(n, total, true);
    LabelColumns& answer = apart.empty() ? x : apart;

    const uint32_t node_groups = vk::ceil_div(n, gpu::kGraphGroup);
    std::vector<float> gamma = pr.gamma.empty() ? std::vector<float>(n, 0.0f) : pr.gamma;
    seed_.ensure(uint64_t(n) * 4);
    gamma_.ensure(uint64_t(n) * 4);
    cmd_.upload(seed_, pr.seed.data(), uint64_t(n) * 4);
    cmd_.upload(gamma_, gamma.data(), uint64_t(n) * 4);
    inv_diag_.ensure(uint64_t(n) * 4);
    coupling_.ensure(uint64_t(n) * 4);
    edge_weights_.ensure(2ull * n * graph.k() * 4);
    const uint32_t most = std::min(total, gpu::kWalkMaxLabels);
    const uint32_t most_width = (most + 3) / 4 * 4;
    for (auto* b : {&prior_, &x_, &b_, &r_, &z_, &p_, &ap_, &best_x_}) b->ensure(uint64_t(n) * most_width * 4);
    partials_.ensure(uint64_t(node_groups) * gpu::kWalkMaxLabels * 4);
    check_partials_.ensure(uint64_t(node_groups) * gpu::kWalkMaxLabels * 4);
    scalars_.ensure(uint64_t(gpu::kWalkMaxLabels) * sizeof(gpu::WalkScalars));
    check_.ensure(uint64_t(gpu::kWalkMaxLabels) * sizeof(gpu::WalkScalars));
    timings_.clear();
    bool multigrid = false;

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
        cmd_.upload(prior_, prior.data(), bytes);
        std::vector<float> x0;
        if (started) x.read(base, labels, width, x0);
        else x0 = prior;
        // Multigrid first; a batch in which some column made no progress at all (its residual
        // never fell below half its start: the V-cycle's float arithmetic diverging on it) is
        // solved again from the same start with the Jacobi preconditioner, slow but steady.
        const bool use_multigrid = o.preconditioner == WalkPreconditioner::Multigrid;
        uint32_t it = 0;
        std::vector<double> best, column;  // per column: its best (multigrid keeps that iterate) and last residual
        std::vector<float> columns_out;    // the batch's answer, node-major, `width` per node
        for (bool jacobi_retry = false;; jacobi_retry = true) {
            cmd_.upload(x_, x0.data(), bytes);

            gpu::WalkPush push[4];
            for (uint32_t mode = 0; mode < 4; ++mode) push[mode] = {{n, graph.k(), labels, node_groups}, {mode, base, 0, 0}};
            const auto& rows = graph.rows();
            const auto& columns = graph.columns();
            const auto& deg = graph.degree_buffer();
            const uint32_t reduce_groups = width / 4;
            cmd_.begin_pass("walk start");
            cmd_.dispatch(walk_kernel("segment/walk_rhs", labels),
                          {rows, columns, graph.adjacency_weights(), deg, seed_, gamma_, prior_, x_, b_, inv_diag_, coupling_, edge_weights_},
                          push[0], node_groups);
            // A x of a start that is 0 on every unknown node (no start, no prior) is 0: no product.
            if (!started && pr.prior.empty()) cmd_.fill(ap_, 0, 0, bytes);
            else cmd_.dispatch(walk_kernel("segment/walk_apply", labels), {rows, columns, edge_weights_, coupling_, seed_, x_, ap_, partials_}, push[0], node_groups);
            cmd_.dispatch(walk_kernel("segment/walk_residual", labels), {b_, ap_, inv_diag_, r_, z_, p_, partials_}, push[3], node_groups);
            cmd_.dispatch("segment/walk_reduce", {partials_, scalars_}, push[3], reduce_groups);
            cmd_.end_pass();
            if (base == 0 && use_multigrid && !jacobi_retry) {
                // The hierarchy (built on the host from the graph's host copy, once for every
                // column batch) comes after the start's passes.
                cmd_.submit_and_wait();
                for (auto& t : cmd_.timings()) timings_.push_back(t);
                stop_if_cancelled(o.cancel);
                multigrid = build_hierarchy(graph, pr.seed, gamma, most_width, o, out);
            }
            if (jacobi_retry) multigrid = false;
            if (multigrid) {
                // r = b - A x, pre-smoothing z = smoother r (walk_residual with the smoother for
                // 1/diag), the V-cycle, r.z, and p = z (beta is 0 at the start).
                cmd_.begin_pass("walk multigrid start");
                // walk_residual's r . pre (pre = smoother r) is the stop test's measure; the cycle's
                // last sweep then writes r . z to partials_.
                cmd_.dispatch(walk_kernel("segment/walk_residual", labels), {b_, ap_, levels_[0].smoother, r_, levels_[0].pre, p_, check_partials_},
                              push[0], node_groups);
                cmd_.dispatch("segment/walk_reduce", {check_partials_, check_}, push[0], reduce_groups);
                record_cycle(graph, labels, o.coarse_scale);
                cmd_.dispatch("segment/walk_reduce", {partials_, scalars_}, push[0], reduce_groups);
                cmd_.dispatch(walk_kernel("segment/walk_direction", labels), {scalars_, z_, p_}, push[0], node_groups);
            } else {
                cmd_.begin_pass("walk start");
                cmd_.dispatch(walk_kernel("segment/walk_residual", labels), {b_, ap_, inv_diag_, r_, z_, p_, partials_}, push[0], node_groups);
                cmd_.dispatch("segment/walk_reduce", {partials_, scalars_}, push[0], reduce_groups);
            }
            cmd_.end_pass();

            // Multigrid gets there in a handful of iterations of tens of ms each, and a check (a
            // reduction and a wait) costs about a ms: it checks after every iteration, never
            // overshooting (every 5 ran a solve done at 6 to 10 unless the rate foresaw it). Jacobi's
            // iterations are cheap: every 25.
            const uint32_t check_every = o.check_every ? o.check_every : multigrid ? 1 : 25;
            it = 0;
            uint32_t best_it = 0;
            double residual = 0;
            best.assign(labels, 1e300);
            column.assign(labels, 0.0);
            for (;;) {
                // The scalars come back with the iterations' own submission: on a discrete GPU a
                // download apiece was two more submissions and waits per check.
                if (!scalars_.mapped()) {
                    cmd_.copy(scalars_, readback_, labels * sizeof(gpu::WalkScalars));
                    if (multigrid) cmd_.copy(check_, readback_, labels * sizeof(gpu::WalkScalars), 0, kCheckAt);
                }
                cmd_.submit_and_wait();
                for (auto& t : cmd_.timings()) timings_.push_back(t);
                stop_if_cancelled(o.cancel);
                auto scalars = [&](const vk::Buffer& b, size_t at) {
                    const auto* from = static_cast<const gpu::WalkScalars*>(b.mapped() ? b.data() : readback_.data());
                    if (!b.mapped()) from += at / sizeof(gpu::WalkScalars);
                    return std::vector<gpu::WalkScalars>(from, from + labels);
                };
                auto s = scalars(scalars_, 0);
                if (multigrid) {
                    // The stop test measures r . r / diag, as the Jacobi solve does, over the nodes in
                    // the hierarchy: level 0's smoother is omega / diag there and 0 on the components it
                    // leaves out (no seed or prior: they keep their start, whatever their r). r . Br of
                    // a V-cycle would grow with the operator's conditioning, asking far more of an
                    // ill-posed scene than of an easy one at the same tolerance. walk_residual (the
                    // start) and walk_update (each step) leave it in check_.
                    const auto c = scalars(check_, kCheckAt);
                    for (uint32_t l = 0; l < labels; ++l) s[l].value.x = c[l].value.x / o.hierarchy.omega;
                }
                residual = 0;
                for (uint32_t l = 0; l < labels; ++l) {
                    const auto& v = s[l].value;
                    column[l] = v.w > 0 ? std::sqrt(std::max(0.0f, v.x) / v.w) : 0.0;
                    residual = std::max(residual, column[l]);
                }
                // Asked for more than float gives, or on a scene whose few seeds leave the operator
                // nearly singular (a real capture with two clicks), multigrid stalls and may blow up,
                // one column at a time: each column's best iterate is kept (best_x_, as the next batch
                // starts) and answers for it, and 15 iterations in which no column improved end the solve.
                uint32_t improved = 0;
                for (uint32_t l = 0; l < labels; ++l)
                    if (column[l] < best[l]) best[l] = column[l], improved |= 1u << l;
                if (improved) best_it = it;
                if (residual <= o.tolerance || it >= o.max_iterations) break;
                if (multigrid && it >= best_it + 15) break;
                cmd_.begin_pass("walk iterations");
                for (uint32_t c = 0; c < check_every && it < o.max_iterations; ++c, ++it) {
                    cmd_.dispatch(walk_kernel("segment/walk_apply", labels), {rows, columns, edge_weights_, coupling_, seed_, p_, ap_, partials_}, push[1],
                                  node_groups);
                    cmd_.dispatch("segment/walk_reduce", {partials_, scalars_}, push[1], reduce_groups);
                    if (multigrid) {
                        // walk_update's z = smoother r is the V-cycle's pre-smoothing on level 0
                        // (its dots are the stop test's; the cycle's last sweep writes r . z). The first
                        // step after a check keeps the columns that improved in best_x_.
                        gpu::WalkPush update = push[0];
                        update.mode.z = c == 0 ? improved : 0u;
                        cmd_.dispatch(walk_kernel("segment/walk_update", labels),
                                      {scalars_, p_, ap_, levels_[0].smoother, x_, r_, levels_[0].pre, check_partials_, best_x_}, update, node_groups);
                        cmd_.dispatch("segment/walk_reduce", {check_partials_, check_}, push[0], reduce_groups);
                        record_cycle(graph, labels, o.coarse_scale);
                    } else {
                        cmd_.dispatch(walk_kernel("segment/walk_update", labels), {scalars_, p_, ap_, inv_diag_, x_, r_, z_, partials_, best_x_},
                                      push[0], node_groups);
                    }
                    cmd_.dispatch("segment/walk_reduce", {partials_, scalars_}, push[2], reduce_groups);
                    cmd_.dispatch(walk_kernel("segment/walk_direction", labels), {scalars_, z_, p_}, push[0], node_groups);
                }
                cmd_.end_pass();
            }
            if (multigrid && *std::max_element(best.begin(), best.end()) > 0.5) {
                out.jacobi_retries += 1;
                continue;
            }
            // A column whose last residual is not its best answers with its best iterate.
            double answered = 0;
            uint32_t from_best = 0;
            for (uint32_t l = 0; l < labels; ++l) {
                if (multigrid && best[l] < column[l]) from_best |= 1u << l;
                answered = std::max(answered, multigrid ? std::min(best[l], column[l]) : column[l]);
            }
            columns_out = vk::download_vector<float>(ctx_, x_, size_t(n) * width);
            if (from_best) {
                const auto kept = vk::download_vector<float>(ctx_, best_x_, size_t(n) * width);
                for (uint32_t i = 0; i < n; ++i)
                    for (uint32_t l = 0; l < labels; ++l)
                        if (from_best >> l & 1u) columns_out[size_t(i) * width + l] = kept[size_t(i) * width + l];
            }
            // The maximum principle: every value is a probability. A solve whose residual test
            // passed may still break it grossly where a weakly joined piece makes the operator
            // nearly singular (multigrid left values of 1e14 there, its residual small):
            // multigrid's answer is then solved again with Jacobi; what is still that far off is
            // clamped and counted. The stop rule's own slack (hundredths) is left as it is.
            const uint64_t outside = walk_values_outside(columns_out, pr.seed, width, labels);
            if (outside && multigrid) {
                out.jacobi_retries += 1;
                out.range_retries += 1;
                continue;
            }
            if (outside) out.out_of_range += clamp_walk_values(columns_out, pr.seed, width, labels);
            out.iterations = std::max(out.iterations, it);
            out.residual = std::max(out.residual, answered);
            break;
        }
        answer.write(base, labels, width, columns_out);
    }
    if (!apart.empty()) x = std::move(apart);
    return out;
}

}  // namespace pg::seg

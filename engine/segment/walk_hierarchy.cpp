#include "engine/segment/walk_hierarchy.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <thread>
#include <utility>

namespace pg::seg {

namespace {

// Per aggregate its nodes, as CSR: what restriction sums.
void children_of(const std::vector<uint32_t>& parent, uint32_t coarse, std::vector<uint32_t>& rows,
                 std::vector<uint32_t>& children) {
    rows.assign(coarse + 1, 0);
    for (uint32_t p : parent)
        if (p != kHierarchyNone) ++rows[p + 1];
    for (uint32_t c = 0; c < coarse; ++c) rows[c + 1] += rows[c];
    children.assign(rows[coarse], 0);
    std::vector<uint32_t> at(rows.begin(), rows.end() - 1);
    for (uint32_t i = 0; i < parent.size(); ++i)
        if (parent[i] != kHierarchyNone) children[at[parent[i]]++] = i;
}

uint32_t find_root(std::vector<uint32_t>& up, uint32_t i) {
    while (up[i] != i) i = up[i] = up[up[i]];
    return i;
}

}  // namespace

uint32_t drop_unanchored(WalkMatrix& a) {
    const uint32_t n = a.size();
    std::vector<uint32_t> up(n);
    for (uint32_t i = 0; i < n; ++i) up[i] = i;
    std::vector<uint8_t> anchored(n, 0);
    for (uint32_t i = 0; i < n; ++i) {
        if (a.diagonal[i] <= 0.0f) continue;
        double e = a.diagonal[i];
        for (uint32_t s = a.rows[i]; s < a.rows[i + 1]; ++s) {
            const uint32_t j = a.columns[s];
            e -= a.weights[s];
            if (a.weights[s] > 0.0f && j != i && a.diagonal[j] > 0.0f) {
                const uint32_t x = find_root(up, i), y = find_root(up, j);
                if (x != y) up[std::max(x, y)] = std::min(x, y);
            }
        }
        // The same threshold as galerkin's excess: below it, the rounding of a bare row.
        if (e > 1e-6 * a.diagonal[i]) anchored[i] = 1;
    }
    std::vector<uint8_t> root_anchored(n, 0);
    for (uint32_t i = 0; i < n; ++i)
        if (anchored[i]) root_anchored[find_root(up, i)] = 1;
    uint32_t dropped = 0;
    for (uint32_t i = 0; i < n; ++i)
        if (a.diagonal[i] > 0.0f && !root_anchored[find_root(up, i)]) a.diagonal[i] = 0.0f, ++dropped;
    return dropped;
}

std::vector<uint32_t> aggregate_nodes(const WalkMatrix& a, const HierarchyOptions& o, uint32_t& count) {
    const uint32_t n = a.size();
    std::vector<uint32_t> parent(n, kHierarchyNone);
    auto in = [&](uint32_t i) { return a.diagonal[i] > 0.0f; };
    // Strength is relative to a node's own largest weight: the kNN affinities span orders of
    // magnitude, and an edge across an object's border is weak only next to the ones inside.
    std::vector<float> top(n, 0.0f);
    for (uint32_t i = 0; i < n; ++i)
        for (uint32_t s = a.rows[i]; s < a.rows[i + 1]; ++s)
            if (a.columns[s] != i && in(a.columns[s])) top[i] = std::max(top[i], a.weights[s]);
    auto strong = [&](uint32_t i, uint32_t s) {
        const uint32_t j = a.columns[s];
        return j != i && in(j) && a.weights[s] > 0.0f && a.weights[s] >= o.strength * top[i];
    };
    count = 0;
    std::vector<std::pair<float, uint32_t>> free;
    // Pass 1: a node whose strong neighbours are all still free starts an aggregate with the
    // strongest of them; aggregates stay apart, and leave room between them for pass 2.
    for (uint32_t i = 0; i < n; ++i) {
        if (!in(i) || parent[i] != kHierarchyNone) continue;
        free.clear();
        bool clear = true;
        for (uint32_t s = a.rows[i]; s < a.rows[i + 1] && clear; ++s) {
            if (!strong(i, s)) continue;
            if (parent[a.columns[s]] != kHierarchyNone) clear = false;
            else free.push_back({a.weights[s], a.columns[s]});
        }
        if (!clear || free.empty()) continue;
        std::sort(free.begin(), free.end(), [](auto& x, auto& y) { return x.first > y.first || (x.first == y.first && x.second < y.second); });
        parent[i] = count;
        for (size_t t = 0; t < free.size() && t + 1 < o.aggregate; ++t) parent[free[t].second] = count;
        ++count;
    }
    // Pass 2: a node left joins the aggregate of its strongest strong neighbour placed by pass 1
    // (not by this pass: no chains that would stretch an aggregate).
    const std::vector<uint32_t> first = parent;
    for (uint32_t i = 0; i < n; ++i) {
        if (!in(i) || parent[i] != kHierarchyNone) continue;
        float best = 0.0f;
        for (uint32_t s = a.rows[i]; s < a.rows[i + 1]; ++s)
            if (strong(i, s) && first[a.columns[s]] != kHierarchyNone && a.weights[s] > best)
                best = a.weights[s], parent[i] = first[a.columns[s]];
    }
    // Pass 3: the rest (no strong neighbour in an aggregate) gather with their free strong
    // neighbours, or stay alone.
    for (uint32_t i = 0; i < n; ++i) {
        if (!in(i) || parent[i] != kHierarchyNone) continue;
        parent[i] = count;
        for (uint32_t s = a.rows[i]; s < a.rows[i + 1]; ++s)
            if (strong(i, s) && parent[a.columns[s]] == kHierarchyNone) parent[a.columns[s]] = count;
        ++count;
    }
    return parent;
}

WalkMatrix galerkin(const WalkMatrix& a, const std::vector<uint32_t>& parent, uint32_t coarse) {
    std::vector<uint32_t> child_rows, children;
    children_of(parent, coarse, child_rows, children);
    // A_c[I][J] = sum over i in I, j in J of A_ij: the weights between aggregates add up. The
    // diagonal is not the children's diagonals less the weights inside (a difference of large
    // numbers that float rounding turns into a lost, even negative, excess on coarse levels),
    // but what it is for D - W + E: the coarse weights' sum plus the children's excesses E (the
    // unary terms and couplings to seeds), which stay exact and non-negative.
    std::vector<double> excess(coarse, 0.0);
    for (uint32_t i = 0; i < a.size(); ++i) {
        if (parent[i] == kHierarchyNone || a.diagonal[i] <= 0.0f) continue;
        double e = a.diagonal[i];
        for (uint32_t s = a.rows[i]; s < a.rows[i + 1]; ++s) e -= a.weights[s];
        if (e > 1e-6 * a.diagonal[i]) excess[parent[i]] += e;  // below: the rounding of a bare row
    }
    // Coarse rows are independent: threads take runs of them, each with its own scratch, and the
    // runs are joined in order. Every row sums the same weights in the same order as one thread
    // would, so the operator is the same bit for bit (the finest level's product was a third of
    // a hierarchy's host time).
    struct Run {
        uint32_t begin = 0, end = 0;
        std::vector<uint32_t> columns, counts;
        std::vector<double> weights, diagonal;
    };
    const uint32_t threads = coarse < 8192 ? 1u : std::clamp(std::thread::hardware_concurrency(), 1u, 8u);
    std::vector<Run> runs(threads);
    auto fill = [&](Run& run) {
        std::vector<uint32_t> row_columns, seen(coarse, kHierarchyNone);
        std::vector<double> acc(coarse, 0.0);
        for (uint32_t c = run.begin; c < run.end; ++c) {
            row_columns.clear();
            for (uint32_t t = child_rows[c]; t < child_rows[c + 1]; ++t) {
                const uint32_t i = children[t];
                for (uint32_t s = a.rows[i]; s < a.rows[i + 1]; ++s) {
                    const uint32_t j = a.columns[s];
                    const uint32_t p = parent[j];
                    if (a.weights[s] == 0.0f || p == kHierarchyNone || p == c) continue;
                    if (seen[p] != c) seen[p] = c, acc[p] = 0.0, row_columns.push_back(p);
                    acc[p] += a.weights[s];
                }
            }
            std::sort(row_columns.begin(), row_columns.end());
            double diag = excess[c];
            for (uint32_t p : row_columns) run.columns.push_back(p), run.weights.push_back(acc[p]), diag += acc[p];
            run.counts.push_back(uint32_t(row_columns.size()));
            run.diagonal.push_back(diag);
        }
    };
    {
        std::vector<std::thread> pool;
        std::vector<std::exception_ptr> failed(threads);
        auto guarded = [&](uint32_t t) {
            try {
                fill(runs[t]);
            } catch (...) {
                failed[t] = std::current_exception();  // (out of memory) rethrown after the join
            }
        };
        for (uint32_t t = 0; t < threads; ++t) {
            runs[t].begin = uint32_t(uint64_t(coarse) * t / threads);
            runs[t].end = uint32_t(uint64_t(coarse) * (t + 1) / threads);
            if (t + 1 < threads) pool.emplace_back(guarded, t);
        }
        guarded(threads - 1);
        for (auto& th : pool) th.join();
        for (auto& e : failed)
            if (e) std::rethrow_exception(e);
    }
    std::vector<double> diagonal(coarse, 0.0);
    std::vector<uint32_t> rows(coarse + 1, 0);
    std::vector<uint32_t> columns;
    std::vector<double> weights;
    for (const Run& run : runs) {
        for (uint32_t c = run.begin; c < run.end; ++c) {
            rows[c + 1] = rows[c] + run.counts[c - run.begin];
            diagonal[c] = run.diagonal[c - run.begin];
        }
        columns.insert(columns.end(), run.columns.begin(), run.columns.end());
        weights.insert(weights.end(), run.weights.begin(), run.weights.end());
    }
    // A coarse node without weights or excess covers a closed component without seed or unary:
    // singular, it has no answer to correct; it leaves the system.
    WalkMatrix out;
    out.diagonal.resize(coarse);
    for (uint32_t c = 0; c < coarse; ++c) out.diagonal[c] = float(diagonal[c]);
    out.rows.assign(coarse + 1, 0);
    for (uint32_t c = 0; c < coarse; ++c) {
        if (out.diagonal[c] > 0.0f)
            for (uint32_t s = rows[c]; s < rows[c + 1]; ++s)
                if (out.diagonal[columns[s]] > 0.0f) {
                    out.columns.push_back(columns[s]);
                    out.weights.push_back(float(weights[s]));
                }
        out.rows[c + 1] = uint32_t(out.columns.size());
    }
    return out;
}

std::vector<float> dense_pseudo_inverse(const WalkMatrix& a) {
    const size_t m = a.size();
    std::vector<double> lo(m * m, 0.0);  // the lower triangle, then L (unit diagonal implied)
    for (size_t i = 0; i < m; ++i) {
        lo[i * m + i] = a.diagonal[i];
        for (uint32_t s = a.rows[i]; s < a.rows[i + 1]; ++s)
            if (a.columns[s] < i) lo[i * m + a.columns[s]] -= a.weights[s];
    }
    std::vector<double> pivot(m, 0.0);  // D^+: 0 where the pivot vanished
    for (size_t k = 0; k < m; ++k) {
        const double d = lo[k * m + k];
        if (!(d > 1e-5 * a.diagonal[k]) || a.diagonal[k] <= 0.0f) {
            for (size_t i = k + 1; i < m; ++i) lo[i * m + k] = 0.0;
            continue;
        }
        pivot[k] = 1.0 / d;
        for (size_t i = k + 1; i < m; ++i) lo[i * m + k] /= d;
        for (size_t i = k + 1; i < m; ++i) {
            const double lik = lo[i * m + k] * d;
            if (lik == 0.0) continue;
            for (size_t j = k + 1; j <= i; ++j) lo[i * m + j] -= lik * lo[j * m + k];
        }
    }
    // Column c of L^-T D^+ L^-1: a forward and a backward substitution on e_c.
    std::vector<float> inv(m * m, 0.0f);
    std::vector<double> y(m);
    for (size_t c = 0; c < m; ++c) {
        std::fill(y.begin(), y.end(), 0.0);
        y[c] = 1.0;
        for (size_t i = c + 1; i < m; ++i) {
            double v = 0.0;
            for (size_t j = c; j < i; ++j) v += lo[i * m + j] * y[j];
            y[i] = -v;
        }
        for (size_t i = 0; i < m; ++i) y[i] *= pivot[i];
        for (size_t i = m; i-- > 0;) {
            double v = y[i];
            for (size_t j = i + 1; j < m; ++j) v -= lo[j * m + i] * y[j];
            y[i] = v;
        }
        for (size_t i = 0; i < m; ++i) inv[i * m + c] = float(y[i]);
    }
    return inv;
}

WalkHierarchy build_walk_hierarchy(WalkMatrix fine, const HierarchyOptions& o) {
    WalkHierarchy h;
    // In the system, such a block's coarse levels end in a nearly singular dense block whose
    // last pivot is rounding: the pseudo-inverse multiplies its constant mode by that, and a
    // start that is not constant there (the coarse answer given to floaters) blows the column up.
    h.dropped = drop_unanchored(fine);
    h.levels.push_back({std::move(fine), {}, {}, {}, {}});
    for (;;) {
        WalkLevel& level = h.levels.back();
        const WalkMatrix& a = level.matrix;
        const uint32_t n = a.size();
        level.smoother.assign(n, 0.0f);
        uint32_t active = 0;
        for (uint32_t i = 0; i < n; ++i)
            if (a.diagonal[i] > 0.0f) level.smoother[i] = o.omega / a.diagonal[i], ++active;
        if (n <= o.coarsest || h.levels.size() >= o.max_levels) break;
        uint32_t coarse = 0;
        auto parent = aggregate_nodes(a, o, coarse);
        // Coarsening that no longer shrinks (nodes without strong neighbours) ends the hierarchy.
        if (coarse == 0 || coarse > active * 9 / 10) break;
        WalkLevel next{galerkin(a, parent, coarse), {}, {}, {}, {}};
        children_of(parent, coarse, level.child_rows, level.children);
        level.parent = std::move(parent);
        h.levels.push_back(std::move(next));
    }
    // A hierarchy that stalled above the dense solve's reach gets none (the caller falls back).
    if (h.levels.back().matrix.size() <= kHierarchyMaxDense) h.coarse_inverse = dense_pseudo_inverse(h.levels.back().matrix);
    return h;
}

}  // namespace pg::seg

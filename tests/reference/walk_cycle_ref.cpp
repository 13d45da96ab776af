#include "tests/reference/walk_cycle_ref.h"

#include <cstddef>

using std::size_t;

namespace pg::ref {

namespace {

// (A v)_i, column c: the operator D - W of one level.
double apply_row(const seg::WalkMatrix& a, const std::vector<double>& v, uint32_t width, uint32_t i, uint32_t c) {
    double y = double(a.diagonal[i]) * v[size_t(i) * width + c];
    for (uint32_t s = a.rows[i]; s < a.rows[i + 1]; ++s) y -= double(a.weights[s]) * v[size_t(a.columns[s]) * width + c];
    return y;
}

std::vector<double> cycle(const seg::WalkHierarchy& h, size_t l, double scale, uint32_t width, const std::vector<double>& r) {
    const seg::WalkLevel& level = h.levels[l];
    const seg::WalkMatrix& a = level.matrix;
    const uint32_t n = a.size();
    std::vector<double> z(size_t(n) * width, 0.0);
    if (l + 1 == h.levels.size()) {
        for (uint32_t i = 0; i < n; ++i)
            for (uint32_t j = 0; j < n; ++j)
                for (uint32_t c = 0; c < width; ++c)
                    z[size_t(i) * width + c] += double(h.coarse_inverse[size_t(i) * n + j]) * r[size_t(j) * width + c];
        return z;
    }
    // Pre-smoothing from 0: one Jacobi step.
    std::vector<double> pre(size_t(n) * width);
    for (uint32_t i = 0; i < n; ++i)
        for (uint32_t c = 0; c < width; ++c) pre[size_t(i) * width + c] = double(level.smoother[i]) * r[size_t(i) * width + c];
    // Restriction of the residual: each aggregate sums its nodes'.
    const uint32_t m = h.levels[l + 1].matrix.size();
    std::vector<double> coarse_r(size_t(m) * width, 0.0);
    for (uint32_t p = 0; p < m; ++p)
        for (uint32_t t = level.child_rows[p]; t < level.child_rows[p + 1]; ++t) {
            const uint32_t i = level.children[t];
            for (uint32_t c = 0; c < width; ++c)
                coarse_r[size_t(p) * width + c] += r[size_t(i) * width + c] - apply_row(a, pre, width, i, c);
        }
    auto coarse_z = cycle(h, l + 1, scale, width, coarse_r);
    // Prolongation (each node adds its aggregate's value, scaled), then post-smoothing.
    std::vector<double> v = pre;
    for (uint32_t i = 0; i < n; ++i)
        if (level.parent[i] != seg::kHierarchyNone)
            for (uint32_t c = 0; c < width; ++c) v[size_t(i) * width + c] += scale * coarse_z[size_t(level.parent[i]) * width + c];
    for (uint32_t i = 0; i < n; ++i)
        for (uint32_t c = 0; c < width; ++c)
            z[size_t(i) * width + c] =
                v[size_t(i) * width + c] + double(level.smoother[i]) * (r[size_t(i) * width + c] - apply_row(a, v, width, i, c));
    return z;
}

}  // namespace

std::vector<double> walk_cycle(const seg::WalkHierarchy& h, double scale, uint32_t width, const std::vector<double>& r) {
    return cycle(h, 0, scale, width, r);
}

}  // namespace pg::ref

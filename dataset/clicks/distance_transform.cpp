#include "dataset/clicks/distance_transform.h"

#include <algorithm>

namespace pg::data::clicks {

void squared_edt_1d(const double* f, int n, double* d, int* sites, double* bounds) {
    // Lower envelope of the parabolas rooted at the finite samples; bounds[k] is where
    // parabola k starts to be the lowest.
    int k = -1;
    for (int q = 0; q < n; ++q) {
        if (!(f[q] < kFar)) continue;
        double s = -kFar;
        while (k >= 0) {
            const int p = sites[k];
            s = ((f[q] + double(q) * q) - (f[p] + double(p) * p)) / (2.0 * (q - p));
            if (s > bounds[k]) break;
            --k;  // parabola k is hidden by the new one everywhere
        }
        ++k;
        sites[k] = q;
        bounds[k] = k == 0 ? -kFar : s;
        bounds[k + 1] = kFar;
    }
    if (k < 0) {
        std::fill(d, d + n, kFar);
        return;
    }
    k = 0;
    for (int q = 0; q < n; ++q) {
        while (bounds[k + 1] < q) ++k;
        const double dq = q - sites[k];
        d[q] = dq * dq + f[sites[k]];
    }
}

namespace {

// One axis of a separable transform over a dense grid: `count` lines of `n` samples,
// line l starting at first(l), samples `stride` apart.
template <class First>
void transform_lines(std::vector<double>& grid, int n, size_t stride, size_t count, First first) {
    std::vector<double> f(n), d(n), bounds(n + 1);
    std::vector<int> sites(n);
    for (size_t l = 0; l < count; ++l) {
        const size_t base = first(l);
        for (int i = 0; i < n; ++i) f[i] = grid[base + i * stride];
        squared_edt_1d(f.data(), n, d.data(), sites.data(), bounds.data());
        for (int i = 0; i < n; ++i) grid[base + i * stride] = d[i];
    }
}

}  // namespace

std::vector<double> squared_distance_to_outside(int w, int h, std::span<const uint8_t> region) {
    // One ring of outside pixels around the image makes the border rule exact.
    const int pw = w + 2, ph = h + 2;
    std::vector<double> grid(size_t(pw) * ph, 0.0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            if (region[size_t(y) * w + x]) grid[size_t(y + 1) * pw + x + 1] = kFar;
    transform_lines(grid, ph, pw, pw, [](size_t l) { return l; });                  // columns
    transform_lines(grid, pw, 1, ph, [pw](size_t l) { return l * size_t(pw); });  // rows
    std::vector<double> out(size_t(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) out[size_t(y) * w + x] = grid[size_t(y + 1) * pw + x + 1];
    return out;
}

void squared_edt_3d(std::vector<double>& grid, int nx, int ny, int nz) {
    const size_t sx = 1, sy = size_t(nx), sz = size_t(nx) * ny;
    transform_lines(grid, nx, sx, size_t(ny) * nz, [sy](size_t l) { return l * sy; });
    transform_lines(grid, ny, sy, size_t(nx) * nz, [nx, sz](size_t l) { return (l / nx) * sz + l % nx; });
    transform_lines(grid, nz, sz, sz, [](size_t l) { return l; });
}

}  // namespace pg::data::clicks

// Terrain: a triangulated height grid. Rays walk the grid cells (2D DDA) from where they
// enter its bounding box; inside a cell the surface is two planes, so the height above
// ground along the ray is piecewise linear and its first zero is exact.
#include <cmath>

#include "dataset/synth/primitives.h"
#include "dataset/synth/sampling.h"

namespace pg::data::synth {
namespace {

class Heightfield final : public Primitive {
public:
    Heightfield(int nx, int ny, double sx, double sy, std::vector<double> h, double base)
        : nx_(nx), ny_(ny), sx_(sx), sy_(sy), h_(std::move(h)), base_(base) {
        dx_ = sx_ / (nx_ - 1);
        dy_ = sy_ / (ny_ - 1);
        double top = base_;
        for (double v : h_) top = std::max(top, v);
        box_ = Aabb{glm::dvec3(-sx_ / 2, -sy_ / 2, base_), glm::dvec3(sx_ / 2, sy_ / 2, top)};
        cell_max_.resize(size_t(nx_ - 1) * (ny_ - 1));
        for (int j = 0; j + 1 < ny_; ++j)
            for (int i = 0; i + 1 < nx_; ++i) {
                cell_max_[cell(i, j)] = std::max({at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)});
                for (int k = 0; k < 2; ++k) {
                    glm::dvec3 a, b, c;
                    triangle(i, j, k, a, b, c);
                    tris_.push(0.5 * glm::length(glm::cross(b - a, c - a)));
                }
            }
    }

    bool intersect(const Ray& r, double t_min, double t_max, double& t) const override {
        const glm::dvec3 inv = 1.0 / r.dir;
        double t0, t1;
        if (!ray_box(r, inv, box_, t0, t1)) return false;
        t0 = std::max(t0, t_min);
        t1 = std::min(t1, t_max);
        if (t0 > t1) return false;
        // Entering through a side or the bottom below the ground: the skirt is hit there.
        const glm::dvec3 p0 = r.origin + t0 * r.dir;
        if (t0 > t_min && p0.z <= height(p0.x, p0.y)) {
            t = t0;
            return true;
        }
        // Cell walk.
        int i = std::clamp(int(std::floor((p0.x + sx_ / 2) / dx_)), 0, nx_ - 2);
        int j = std::clamp(int(std::floor((p0.y + sy_ / 2) / dy_)), 0, ny_ - 2);
        const int step_i = r.dir.x > 0 ? 1 : -1, step_j = r.dir.y > 0 ? 1 : -1;
        auto next_edge = [&](int a, int step, double origin, double d, double inv_d, double cell0, double size) {
            if (d == 0.0) return kInf;
            const double edge = cell0 + (a + (step > 0 ? 1 : 0)) * size;
            return (edge - origin) * inv_d;
        };
        double tx = next_edge(i, step_i, r.origin.x, r.dir.x, inv.x, -sx_ / 2, dx_);
        double ty = next_edge(j, step_j, r.origin.y, r.dir.y, inv.y, -sy_ / 2, dy_);
        const double dtx = r.dir.x == 0.0 ? kInf : dx_ * std::abs(inv.x), dty = r.dir.y == 0.0 ? kInf : dy_ * std::abs(inv.y);
        double ta = t0;
        for (int guard = 0; guard < 4 * (nx_ + ny_) + 8; ++guard) {
            const double tb = std::min({tx, ty, t1});
            if (hit_in_cell(r, i, j, ta, tb, t)) return true;
            if (tb >= t1) return false;
            ta = tb;
            if (tx <= ty) {
                i += step_i;
                tx += dtx;
            } else {
                j += step_j;
                ty += dty;
            }
            if (i < 0 || j < 0 || i > nx_ - 2 || j > ny_ - 2) return false;
        }
        return false;
    }

    bool contains(const glm::dvec3& p) const override {
        if (p.x < box_.lo.x || p.x > box_.hi.x || p.y < box_.lo.y || p.y > box_.hi.y || p.z < base_) return false;
        return p.z <= height(p.x, p.y);
    }

    double area() const override { return tris_.total(); }
    Aabb bounds() const override { return box_; }

    SurfacePoint sample(Rng& rng) const override {
        const size_t k = tris_.pick(rng);
        const int c = int(k / 2), i = c % (nx_ - 1), j = c / (nx_ - 1);
        glm::dvec3 a, b, d;
        triangle(i, j, int(k % 2), a, b, d);
        SurfacePoint s;
        s.p = uniform_in_triangle(rng, a, b, d);
        s.n = glm::normalize(glm::cross(b - a, d - a));
        s.tangent = glm::normalize(glm::dvec3(1, 0, 0) - s.n * s.n.x);
        s.feature = 2.0 * std::max(dx_, dy_);
        return s;
    }

private:
    size_t cell(int i, int j) const { return size_t(j) * (nx_ - 1) + i; }
    double at(int i, int j) const { return h_[size_t(j) * nx_ + i]; }
    glm::dvec3 vertex(int i, int j) const { return {-sx_ / 2 + i * dx_, -sy_ / 2 + j * dy_, at(i, j)}; }

    // Triangles of a cell, counter-clockwise seen from above: (00, 10, 11) and (00, 11, 01).
    void triangle(int i, int j, int k, glm::dvec3& a, glm::dvec3& b, glm::dvec3& c) const {
        a = vertex(i, j);
        b = k == 0 ? vertex(i + 1, j) : vertex(i + 1, j + 1);
        c = k == 0 ? vertex(i + 1, j + 1) : vertex(i, j + 1);
    }

    // Ground height of cell (i, j)'s triangles at (x, y), extrapolated outside the cell.
    double cell_height(int i, int j, double x, double y) const {
        const double fx = (x - (-sx_ / 2 + i * dx_)) / dx_, fy = (y - (-sy_ / 2 + j * dy_)) / dy_;
        const double h00 = at(i, j), h10 = at(i + 1, j), h01 = at(i, j + 1), h11 = at(i + 1, j + 1);
        return fx >= fy ? h00 + fx * (h10 - h00) + fy * (h11 - h10) : h00 + fy * (h01 - h00) + fx * (h11 - h01);
    }

    double height(double x, double y) const {
        const int i = std::clamp(int(std::floor((x + sx_ / 2) / dx_)), 0, nx_ - 2);
        const int j = std::clamp(int(std::floor((y + sy_ / 2) / dy_)), 0, ny_ - 2);
        return cell_height(i, j, x, y);
    }

    // First t in [ta, tb] where the ray is at or below cell (i, j)'s surface.
    bool hit_in_cell(const Ray& r, int i, int j, double ta, double tb, double& t) const {
        if (std::min(r.origin.z + ta * r.dir.z, r.origin.z + tb * r.dir.z) > cell_max_[cell(i, j)]) return false;
        // The diagonal fx = fy splits the segment into two linear pieces.
        const double x0 = -sx_ / 2 + i * dx_, y0 = -sy_ / 2 + j * dy_;
        const double g0 = (r.origin.x - x0) / dx_ - (r.origin.y - y0) / dy_, g1 = r.dir.x / dx_ - r.dir.y / dy_;
        double cuts[3] = {ta, tb, tb};
        int n = 2;
        if (g1 != 0.0) {
            const double td = -g0 / g1;
            if (td > ta && td < tb) {
                cuts[1] = td;
                n = 3;
            }
        }
        for (int k = 0; k + 1 < n; ++k) {
            const double a = cuts[k], b = cuts[k + 1];
            // Evaluate each piece inside itself so both ends use the same triangle.
            const double mid = 0.5 * (a + b);
            const glm::dvec3 pm = r.origin + mid * r.dir;
            const bool lower = (pm.x - x0) / dx_ >= (pm.y - y0) / dy_;
            auto piece = [&](double tt) {
                const glm::dvec3 p = r.origin + tt * r.dir;
                const double fx = (p.x - x0) / dx_, fy = (p.y - y0) / dy_;
                const double h00 = at(i, j), h10 = at(i + 1, j), h01 = at(i, j + 1), h11 = at(i + 1, j + 1);
                const double h = lower ? h00 + fx * (h10 - h00) + fy * (h11 - h10) : h00 + fy * (h01 - h00) + fx * (h11 - h01);
                return p.z - h;
            };
            const double fa = piece(a), fb = piece(b);
            if (fa <= 0.0) {  // only by rounding at a cell boundary
                t = a;
                return true;
            }
            if (fb <= 0.0) {
                t = a + (b - a) * fa / (fa - fb);
                return true;
            }
        }
        return false;
    }

    int nx_, ny_;
    double sx_, sy_, dx_ = 1, dy_ = 1;
    std::vector<double> h_;
    double base_;
    Aabb box_;
    std::vector<double> cell_max_;
    AreaTable tris_;
};

}  // namespace

PrimitivePtr make_heightfield(int nx, int ny, double size_x, double size_y, std::vector<double> heights, double base) {
    return std::make_shared<Heightfield>(std::max(nx, 2), std::max(ny, 2), size_x, size_y, std::move(heights), base);
}

}  // namespace pg::data::synth

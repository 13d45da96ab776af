#include "app/cli/synthetic_crop.h"

#include <cmath>
#include <set>
#include <tuple>

#include "dataset/error.h"
#include "dataset/random.h"

namespace pg::app {

nn::Ptv3Input synthetic_crop(int n, int channels, double grid, uint64_t seed) {
    data::Rng rng(seed);
    struct Shape {
        bool sphere;
        double cx, cy, cz, sx, sy, sz;
    };
    std::vector<Shape> shapes;
    const double extent = std::max(1.0, std::sqrt(double(n)) * grid * 0.35);
    for (int i = 0; i < 5; ++i) {
        double s = rng.uniform(0.15, 0.35) * extent;
        shapes.push_back({i % 2 == 1, rng.uniform(-0.6, 0.6) * extent, rng.uniform(-0.6, 0.6) * extent, s, s,
                          rng.uniform(0.8, 1.2) * s, rng.uniform(0.8, 1.6) * s});
    }
    std::set<std::tuple<long, long, long>> seen;
    nn::Ptv3Input in;
    size_t guard = 0;
    while (int(in.size()) < n && ++guard < size_t(n) * 200) {
        double x, y, z;
        const int pick = rng.below(int(shapes.size()) + 1);
        if (pick == int(shapes.size())) {  // floor
            x = rng.uniform(-extent, extent), y = rng.uniform(-extent, extent), z = 0;
        } else {
            const Shape& s = shapes[size_t(pick)];
            if (s.sphere) {
                double u = rng.normal(), v = rng.normal(), w = rng.normal(), r = std::sqrt(u * u + v * v + w * w) + 1e-12;
                x = s.cx + s.sx * u / r, y = s.cy + s.sx * v / r, z = s.cz + s.sx * w / r;
            } else {
                double p[3] = {rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)};
                p[rng.below(3)] = rng.sign();
                x = s.cx + s.sx * 0.5 * p[0], y = s.cy + s.sy * 0.5 * p[1], z = s.sz * 0.5 * (1 + p[2]);
            }
        }
        if (!seen.insert({std::lround(std::floor(x / grid)), std::lround(std::floor(y / grid)),
                          std::lround(std::floor(z / grid))})
                 .second)
            continue;
        in.coord.insert(in.coord.end(), {float(x), float(y), float(z)});
    }
    if (int(in.size()) < n) throw data::InputError("--points", "could not place " + std::to_string(n) + " distinct voxels");
    // Click weights: a positive click on the first shape, a negative one on the second.
    const double sigma = 0.15 * extent;
    const size_t m = in.size();
    in.feat.assign(m * size_t(channels), 0.0f);
    for (size_t i = 0; i < m; ++i)
        for (int ch = 0; ch < std::min(channels, 2); ++ch) {
            const Shape& s = shapes[size_t(ch)];
            double dx = in.coord[3 * i] - s.cx, dy = in.coord[3 * i + 1] - s.cy, dz = in.coord[3 * i + 2] - s.sz;
            in.feat[i * size_t(channels) + size_t(ch)] = float(std::exp(-(dx * dx + dy * dy + dz * dz) / (2 * sigma * sigma)));
        }
    return in;
}

}  // namespace pg::app

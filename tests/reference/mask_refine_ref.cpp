#include "tests/reference/mask_refine_ref.h"

#include <algorithm>
#include <map>
#include <set>
#include <utility>

namespace pg::ref {

namespace {

struct Grid {
    int w, h;
    bool inside(int x, int y) const { return x >= 0 && y >= 0 && x < w && y < h; }
    size_t at(int x, int y) const { return size_t(y) * size_t(w) + size_t(x); }
};

// Pixels of the component of `seed` under `joined`, visited breadth-first.
template <class Joined>
std::vector<size_t> flood(Grid g, size_t seed, bool eight, Joined joined, std::vector<uint8_t>& seen) {
    static const int d4[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
    static const int d8[8][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {1, -1}, {-1, 1}, {-1, -1}};
    std::vector<size_t> pixels{seed};
    seen[seed] = 1;
    for (size_t i = 0; i < pixels.size(); ++i) {
        const int x = int(pixels[i] % size_t(g.w)), y = int(pixels[i] / size_t(g.w));
        for (int k = 0; k < (eight ? 8 : 4); ++k) {
            const int nx = x + (eight ? d8[k][0] : d4[k][0]), ny = y + (eight ? d8[k][1] : d4[k][1]);
            if (!g.inside(nx, ny)) continue;
            const size_t q = g.at(nx, ny);
            if (!seen[q] && joined(q)) {
                seen[q] = 1;
                pixels.push_back(q);
            }
        }
    }
    return pixels;
}

}  // namespace

LabelImage close_labels(const LabelImage& labels, int width, int height, int radius) {
    const Grid g{width, height};
    LabelImage out = labels;
    if (radius <= 0) return out;
    const int r = radius;
    // Each instance's bounding box: its dilation lies within r of it, its closing too.
    struct Box { int x0, y0, x1, y1; };
    std::map<uint32_t, Box> boxes;  // ascending ids: the first to claim a pixel is the smallest
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const uint32_t k = labels[g.at(x, y)];
            if (k == 0) continue;
            auto [it, fresh] = boxes.try_emplace(k, Box{x, y, x, y});
            if (!fresh) it->second = {std::min(it->second.x0, x), std::min(it->second.y0, y),
                                      std::max(it->second.x1, x), std::max(it->second.y1, y)};
        }
    for (auto& [k, b] : boxes) {
        // A window of the image around the box, as far as the erosion of the closing reaches
        // (2r); the square's max and min are taken along rows, then along columns.
        const int wx0 = std::max(0, b.x0 - 2 * r), wy0 = std::max(0, b.y0 - 2 * r);
        const int wx1 = std::min(width - 1, b.x1 + 2 * r), wy1 = std::min(height - 1, b.y1 + 2 * r);
        const int ww = wx1 - wx0 + 1, wh = wy1 - wy0 + 1;
        auto at = [&](int x, int y) { return size_t(y - wy0) * size_t(ww) + size_t(x - wx0); };
        // Along one axis over the window; pixels off the image are skipped (for the dilation
        // they are not k, for the erosion they are k), so `fold` only sees pixels in it.
        auto pass = [&](const std::vector<uint8_t>& in, bool along_x, bool dilate) {
            std::vector<uint8_t> res(in.size());
            for (int y = wy0; y <= wy1; ++y)
                for (int x = wx0; x <= wx1; ++x) {
                    bool v = !dilate;
                    for (int d = -r; d <= r; ++d) {
                        const int u = along_x ? x + d : x, t = along_x ? y : y + d;
                        if (!g.inside(u, t)) continue;
                        // Past the window (yet in the image): farther than 2r from the box, so
                        // neither k nor in its dilation.
                        const bool bit = u >= wx0 && u <= wx1 && t >= wy0 && t <= wy1 && in[at(u, t)];
                        v = dilate ? (v || bit) : (v && bit);
                    }
                    res[at(x, y)] = v;
                }
            return res;
        };
        std::vector<uint8_t> mask(size_t(ww) * size_t(wh));
        for (int y = wy0; y <= wy1; ++y)
            for (int x = wx0; x <= wx1; ++x) mask[at(x, y)] = labels[g.at(x, y)] == k;
        const auto dilated = pass(pass(mask, true, true), false, true);
        const auto closed = pass(pass(dilated, true, false), false, false);
        for (int y = wy0; y <= wy1; ++y)
            for (int x = wx0; x <= wx1; ++x)
                if (labels[g.at(x, y)] == 0 && out[g.at(x, y)] == 0 && closed[at(x, y)]) out[g.at(x, y)] = k;
    }
    return out;
}

LabelImage fill_label_holes(const LabelImage& labels, int width, int height) {
    const Grid g{width, height};
    LabelImage out = labels;
    std::vector<uint8_t> seen(labels.size(), 0);
    for (size_t seed = 0; seed < labels.size(); ++seed) {
        if (labels[seed] != 0 || seen[seed]) continue;
        const auto hole = flood(g, seed, false, [&](size_t q) { return labels[q] == 0; }, seen);
        bool border = false;
        std::set<uint32_t> around;
        for (size_t p : hole) {
            const int x = int(p % size_t(width)), y = int(p / size_t(width));
            if (x == 0 || y == 0 || x == width - 1 || y == height - 1) border = true;
            const int d4[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
            for (auto& d : d4)
                if (g.inside(x + d[0], y + d[1]) && labels[g.at(x + d[0], y + d[1])] != 0)
                    around.insert(labels[g.at(x + d[0], y + d[1])]);
        }
        if (!border && around.size() == 1)
            for (size_t p : hole) out[p] = *around.begin();
    }
    return out;
}

LabelImage keep_largest_components(const LabelImage& labels, int width, int height) {
    const Grid g{width, height};
    std::vector<uint8_t> seen(labels.size(), 0);
    // Per instance: its components in order of their lowest pixel (the scan meets that first).
    std::map<uint32_t, std::vector<std::vector<size_t>>> parts;
    for (size_t seed = 0; seed < labels.size(); ++seed) {
        if (labels[seed] == 0 || seen[seed]) continue;
        const uint32_t k = labels[seed];
        parts[k].push_back(flood(g, seed, true, [&](size_t q) { return labels[q] == k; }, seen));
    }
    LabelImage out = labels;
    for (auto& [k, comps] : parts) {
        size_t best = 0;
        for (size_t i = 1; i < comps.size(); ++i)
            if (comps[i].size() > comps[best].size()) best = i;  // strictly larger: ties keep the earlier
        for (size_t i = 0; i < comps.size(); ++i)
            if (i != best)
                for (size_t p : comps[i]) out[p] = 0;
    }
    return out;
}

LabelImage refine_labels(const LabelImage& labels, int width, int height, const std::vector<int>& closing_radii,
                         bool fill_holes, bool largest_component) {
    LabelImage cur = labels;
    for (int r : closing_radii) cur = close_labels(cur, width, height, r);
    if (fill_holes) cur = fill_label_holes(cur, width, height);
    if (largest_component) cur = keep_largest_components(cur, width, height);
    return cur;
}

}  // namespace pg::ref

#include "tests/reference/label_raster_ref.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pg::ref {
namespace {

constexpr float kMinTransmittance = 1e-4f;

// q^T d d form of the symmetric matrix [[q.x, q.y], [q.y, q.z]], evaluated in the GPU's order.
float quadratic_form(glm::vec3 q, float dx, float dy) {
    const float xx = q.x * dx * dx;
    const float xy = 2.0f * q.y * dx * dy;
    const float yy = q.z * dy * dy;
    return xx + xy + yy;
}

// Whether the ellipse d^T Q d <= r2 around m reaches a pixel centre of tile (tx, ty): the
// minimum of the convex form over the box of the tile's pixel centres, on an edge when m is
// outside the box (shaders/render/tile_test.glsl).
bool ellipse_hits_tile(glm::vec2 m, glm::vec3 q, float r2, int tx, int ty, int width, int height) {
    const glm::vec2 lo = glm::vec2(float(tx * kLabelTile), float(ty * kLabelTile)) + 0.5f;
    const glm::vec2 hi = glm::vec2(float(std::min((tx + 1) * kLabelTile, width)),
                                   float(std::min((ty + 1) * kLabelTile, height))) - 0.5f;
    if (m.x >= lo.x && m.y >= lo.y && m.x <= hi.x && m.y <= hi.y) return true;
    float best = 3.4e38f;
    for (float ey : {lo.y, hi.y}) {
        const float dy = ey - m.y;
        const float x = std::clamp(m.x - q.y * dy / q.x, lo.x, hi.x);
        best = std::min(best, quadratic_form(q, x - m.x, dy));
    }
    for (float ex : {lo.x, hi.x}) {
        const float dx = ex - m.x;
        const float y = std::clamp(m.y - q.y * dx / q.z, lo.y, hi.y);
        best = std::min(best, quadratic_form(q, dx, y - m.y));
    }
    return best <= r2;
}

// Labels > 0 of one pixel with their weights, at most kLabelSlots of them.
struct LabelSlots {
    uint32_t label[kLabelSlots] = {};  // 0: empty
    float weight[kLabelSlots] = {};
    float background = 0.0f;           // weight of label 0
    bool overflowed = false;

    void add(uint32_t l, float w) {
        if (l == 0) {
            background += w;
            return;
        }
        for (int s = 0; s < kLabelSlots; ++s)
            if (label[s] == l) {
                weight[s] += w;
                return;
            }
        // Not held: an empty slot, else the smallest weight (ties: the larger label) makes room.
        int victim = 0;
        for (int s = 1; s < kLabelSlots; ++s)
            if (weight[s] < weight[victim] || (weight[s] == weight[victim] && label[s] > label[victim])) victim = s;
        if (label[victim] != 0) overflowed = true;
        label[victim] = l;
        weight[victim] = w;
    }

    // Largest weight, ties to the smaller label; label 0 takes part.
    uint32_t winner() const {
        uint32_t best = 0;
        float best_w = background;
        for (int s = 0; s < kLabelSlots; ++s)
            if (label[s] != 0 && (weight[s] > best_w || (weight[s] == best_w && label[s] < best))) {
                best = label[s];
                best_w = weight[s];
            }
        return best;
    }
};

}  // namespace

TileBins bin_gaussians(const pg::data::GaussianCloud& cloud, const pg::data::Camera& camera, const RefOptions& options) {
    TileBins bins;
    bins.width = camera.width;
    bins.height = camera.height;
    if (bins.width <= 0 || bins.height <= 0) throw std::invalid_argument("bin_gaussians: camera has no pixels");
    bins.tiles_x = (bins.width + kLabelTile - 1) / kLabelTile;
    bins.tiles_y = (bins.height + kLabelTile - 1) / kLabelTile;
    bins.tiles.resize(size_t(bins.tiles_x) * size_t(bins.tiles_y));

    for (size_t i = 0; i < cloud.size(); ++i) {
        ProjectedGaussian g;
        if (project_gaussian(cloud, i, camera, options, g)) bins.splats.push_back(g);
    }
    std::sort(bins.splats.begin(), bins.splats.end(), [](const ProjectedGaussian& l, const ProjectedGaussian& r) {
        return l.depth < r.depth || (l.depth == r.depth && l.index < r.index);
    });

    const float w = float(bins.width), h = float(bins.height);
    for (size_t s = 0; s < bins.splats.size(); ++s) {
        const ProjectedGaussian& g = bins.splats[s];
        // Support o exp(-q/2) >= 1/255, i.e. q <= 2 ln(255 o), widened like preprocess.comp.
        const float extent2 = 2.0f * std::log(255.0f * g.opacity) * 1.0001f + 1e-4f;
        const float half_x = std::sqrt(extent2 * g.cov2d.x), half_y = std::sqrt(extent2 * g.cov2d.z);
        // Pixels whose centres (k + 0.5) can lie inside, then their tiles.
        const float lo_x = std::ceil(g.mean2d.x - half_x - 0.5f), lo_y = std::ceil(g.mean2d.y - half_y - 0.5f);
        const float hi_x = std::floor(g.mean2d.x + half_x - 0.5f), hi_y = std::floor(g.mean2d.y + half_y - 0.5f);
        if (hi_x < 0.0f || hi_y < 0.0f || lo_x > w - 1.0f || lo_y > h - 1.0f || lo_x > hi_x || lo_y > hi_y) continue;
        const int t0x = int(std::max(lo_x, 0.0f)) / kLabelTile, t0y = int(std::max(lo_y, 0.0f)) / kLabelTile;
        const int t1x = int(std::min(hi_x, w - 1.0f)) / kLabelTile, t1y = int(std::min(hi_y, h - 1.0f)) / kLabelTile;
        const bool test = (t1x - t0x + 1) * (t1y - t0y + 1) > 2;
        for (int ty = t0y; ty <= t1y; ++ty)
            for (int tx = t0x; tx <= t1x; ++tx)
                if (!test || ellipse_hits_tile(g.mean2d, g.conic, extent2, tx, ty, bins.width, bins.height))
                    bins.tiles[size_t(ty) * bins.tiles_x + tx].push_back(uint32_t(s));
    }
    return bins;
}

std::vector<uint32_t> label_reference(const pg::data::GaussianCloud& cloud, const pg::data::Camera& camera,
                                      const std::vector<uint32_t>& labels, LabelMode mode, const RefOptions& options,
                                      LabelStats* stats) {
    const TileBins bins = bin_gaussians(cloud, camera, options);
    auto label_of = [&](const ProjectedGaussian& g) { return g.index < labels.size() ? labels[g.index] : 0u; };
    std::vector<uint32_t> image(size_t(bins.width) * size_t(bins.height), 0);
    if (stats) *stats = {};

    for (int y = 0; y < bins.height; ++y) {
        for (int x = 0; x < bins.width; ++x) {
            const auto& list = bins.tiles[size_t(y / kLabelTile) * bins.tiles_x + x / kLabelTile];
            const glm::vec2 centre(float(x) + 0.5f, float(y) + 0.5f);
            uint32_t result = 0;
            if (mode == LabelMode::Paper) {
                // Algorithm 1: the whole list, no transmittance cut-off; the first hit wins.
                for (uint32_t s : list) {
                    const ProjectedGaussian& g = bins.splats[s];
                    const uint32_t l = label_of(g);
                    if (l == 0) continue;
                    const glm::vec2 d = g.mean2d - centre;
                    const float dx2 = d.x * d.x, dy2 = d.y * d.y;
                    if (dx2 + dy2 <= kLabelRho2Max) {
                        result = l;
                        break;
                    }
                }
            } else {
                // The renderer's blending; weights alpha * T per label.
                LabelSlots slots;
                float T = 1.0f;
                for (uint32_t s : list) {
                    const ProjectedGaussian& g = bins.splats[s];
                    const float alpha = splat_alpha(g, centre);
                    if (alpha == 0.0f) continue;
                    const float test_T = T * (1.0f - alpha);
                    if (test_T < kMinTransmittance) break;
                    slots.add(label_of(g), alpha * T);
                    T = test_T;
                }
                result = 1.0f - T >= kLabelMinCoverage ? slots.winner() : 0u;
                if (stats && slots.overflowed) ++stats->overflow_pixels;
            }
            image[size_t(y) * bins.width + x] = result;
        }
    }
    return image;
}

}  // namespace pg::ref

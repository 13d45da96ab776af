#include "engine/segment/pixel_candidates.h"

#include <algorithm>
#include <cmath>
#include <thread>

#include "shaders/render/render_shared.h"

namespace pg::seg {

namespace {

constexpr int kBin = 16;                // pixels per bin side
constexpr uint64_t kMostBins = 64;      // a footprint over more bins is tested at every pixel instead
// Opacity at most 1 gives the widest extent: a first test with it spares most Gaussians the
// opacity's exp and log.
const double kWidest = 2.0 * std::log(255.0) * 1.0001 + 1e-4;

// Where a Gaussian's centre lands and a bound on its 2D variances, from its largest scale
// squared (s2) alone: a row of the projection's Jacobian times a rotation is as long as the
// Jacobian's row, so the variances are at most |J row|^2 x s2 + the low-pass. False behind the
// camera.
struct Projected {
    double sx = 0, sy = 0, var_x = 0, var_y = 0;
};
bool project(const data::Camera& camera, const glm::vec3& mean, double s2, Projected& f) {
    const glm::dvec3 p = camera.R * glm::dvec3(mean) + camera.t;
    if (!(p.z > 0.0)) return false;
    const double rx = p.x / p.z, ry = p.y / p.z;
    f.var_x = camera.fx * camera.fx / (p.z * p.z) * (1.0 + rx * rx) * s2 + render::gpu::kLowPass;
    f.var_y = camera.fy * camera.fy / (p.z * p.z) * (1.0 + ry * ry) * s2 + render::gpu::kLowPass;
    f.sx = camera.fx * rx + camera.cx;
    f.sy = camera.fy * ry + camera.cy;
    return true;
}

// Whether Gaussian i may reach pixel (px, py): within its projected bound at the widest extent
// (the unfiltered opacity; tested first, it spares most Gaussians the opacity's exp and log),
// then at its own opacity, with a pixel of slack for float rounding. The renderer's own tests
// cull the rest, so the pixel's contributors are the same. NaN bounds (a broken Gaussian) keep
// it: the renderer decides.
bool reaches(const data::GaussianCloud& cloud, const data::Camera& camera, uint32_t i, int px, int py) {
    const glm::vec3 ls = cloud.log_scale[i];
    Projected f;
    if (!project(camera, cloud.mean[i], std::exp(2.0 * double(std::max(ls.x, std::max(ls.y, ls.z)))), f)) return false;
    const double dx = std::abs(px + 0.5 - f.sx), dy = std::abs(py + 0.5 - f.sy);
    if (dx > std::sqrt(kWidest * f.var_x) * 1.01 + 1.0 || dy > std::sqrt(kWidest * f.var_y) * 1.01 + 1.0) return false;
    const double opacity = 1.0 / (1.0 + std::exp(-double(cloud.opacity_logit[i])));
    if (opacity < render::gpu::kAlphaMin) return false;
    const double extent2 = 2.0 * std::log(255.0 * opacity) * 1.0001 + 1e-4;
    return !(dx > std::sqrt(extent2 * f.var_x) * 1.01 + 1.0 || dy > std::sqrt(extent2 * f.var_y) * 1.01 + 1.0);
}

// Cores for a pass over n Gaussians: one below 65,536 (threads would cost more than they save).
uint32_t cores_for(uint32_t n) { return n < (1u << 16) ? 1u : std::clamp(std::thread::hardware_concurrency(), 1u, 16u); }

// fn(t, begin, end) on `threads` contiguous ranges of [0, n), range 0 on this thread: joined in
// range order, their outputs keep id order.
template <class Fn>
void in_ranges(uint32_t n, uint32_t threads, Fn&& fn) {
    auto range = [&](uint32_t t) { fn(t, uint32_t(uint64_t(n) * t / threads), uint32_t(uint64_t(n) * (t + 1) / threads)); };
    std::vector<std::thread> pool;
    for (uint32_t t = 1; t < threads; ++t) pool.emplace_back(range, t);
    range(0);
    for (auto& th : pool) th.join();
}

bool same_view(const data::Camera& a, const data::Camera& b) {
    return a.width == b.width && a.height == b.height && a.fx == b.fx && a.fy == b.fy && a.cx == b.cx && a.cy == b.cy &&
           a.R == b.R && a.t == b.t;
}

}  // namespace

std::vector<uint32_t> pixel_candidates(const data::GaussianCloud& cloud, const data::Camera& camera, int px, int py) {
    // Contiguous ranges on the cores, joined in order: the same ascending list as one loop (a
    // view's first click on 6 M Gaussians scans them all).
    const uint32_t n = uint32_t(cloud.size()), threads = cores_for(n);
    std::vector<std::vector<uint32_t>> part(threads);
    in_ranges(n, threads, [&](uint32_t t, uint32_t begin, uint32_t end) {
        for (uint32_t i = begin; i < end; ++i)
            if (reaches(cloud, camera, i, px, py)) part[t].push_back(i);
    });
    std::vector<uint32_t> out = std::move(part[0]);
    for (uint32_t t = 1; t < threads; ++t) out.insert(out.end(), part[t].begin(), part[t].end());
    return out;
}

void PixelBins::prepare(const data::GaussianCloud& cloud) {
    if (prepared_ == &cloud && size_.size() == cloud.size()) return;
    // The view-independent half of each footprint's bound, once per cloud: a view's bins then
    // cost a projection and a square root per Gaussian.
    const uint32_t n = uint32_t(cloud.size());
    size_.resize(n);
    in_ranges(n, cores_for(n), [&](uint32_t, uint32_t begin, uint32_t end) {
        for (uint32_t i = begin; i < end; ++i) {
            // In float (a third of the time), rounded outwards: the bins' bounds have a pixel of
            // slack, and the exact test runs in double per click. Only what is surely fainter than
            // the renderer's floor is left out.
            const glm::vec3 ls = cloud.log_scale[i];
            const float s2 = std::exp(2.0f * std::max(ls.x, std::max(ls.y, ls.z)));
            const float opacity = 1.0f / (1.0f + std::exp(-cloud.opacity_logit[i]));
            size_[i] = glm::vec2(s2, opacity < 0.999f * render::gpu::kAlphaMin
                                         ? -1.0f
                                         : std::max(2.0f * std::log(255.0f * opacity) * 1.0002f + 2e-4f, 2e-4f));
        }
    });
    prepared_ = &cloud;
}

PixelBins::View PixelBins::bin(const data::GaussianCloud& cloud, const data::Camera& camera) {
    prepare(cloud);
    View v;
    v.camera = camera;
    v.columns = uint32_t((std::max(camera.width, 1) + kBin - 1) / kBin);
    v.rows = uint32_t((std::max(camera.height, 1) + kBin - 1) / kBin);
    // Each footprint's bins: the pixels whose centres its bound at its own opacity holds (never
    // wider than at the widest), a pixel wider each way (rounding); the exact test runs again per
    // click, so a bin may hold more than it needs. Two passes, counting then filling, so nothing
    // per Gaussian is kept.
    enum class Where { Nowhere, Bins, Always };
    struct Rect {
        uint32_t x0, y0, x1, y1;
    };
    auto rect_of = [&](uint32_t i, Rect& r) {
        Projected f;
        if (size_[i].y < 0.0f || !project(camera, cloud.mean[i], double(size_[i].x), f)) return Where::Nowhere;
        const double sx = f.sx, sy = f.sy;
        const double bx = std::sqrt(double(size_[i].y) * f.var_x) * 1.01 + 1.0, by = std::sqrt(double(size_[i].y) * f.var_y) * 1.01 + 1.0;
        const double lo_x = std::floor(sx - bx - 0.5) - 1.0, hi_x = std::ceil(sx + bx - 0.5) + 1.0;
        const double lo_y = std::floor(sy - by - 0.5) - 1.0, hi_y = std::ceil(sy + by - 0.5) + 1.0;
        if (!std::isfinite(lo_x) || !std::isfinite(hi_x) || !std::isfinite(lo_y) || !std::isfinite(hi_y)) return Where::Always;
        if (hi_x < 0 || hi_y < 0 || lo_x >= camera.width || lo_y >= camera.height) return Where::Nowhere;
        r.x0 = uint32_t(std::max(lo_x, 0.0)) / kBin, r.y0 = uint32_t(std::max(lo_y, 0.0)) / kBin;
        r.x1 = uint32_t(std::min(hi_x, double(camera.width - 1))) / kBin;
        r.y1 = uint32_t(std::min(hi_y, double(camera.height - 1))) / kBin;
        return uint64_t(r.x1 - r.x0 + 1) * (r.y1 - r.y0 + 1) > kMostBins ? Where::Always : Where::Bins;
    };
    // On the cores, each a contiguous range of ids: a bin holds range 0's ids, then range 1's, ...,
    // so it ascends as one pass would fill it.
    const uint32_t n = uint32_t(cloud.size()), threads = cores_for(n);
    const size_t bins = size_t(v.columns) * v.rows;
    std::vector<std::vector<uint32_t>> fill(threads, std::vector<uint32_t>(bins, 0)), always(threads);
    in_ranges(n, threads, [&](uint32_t t, uint32_t begin, uint32_t end) {
        Rect r{};
        for (uint32_t i = begin; i < end; ++i)
            if (rect_of(i, r) == Where::Bins)
                for (uint32_t y = r.y0; y <= r.y1; ++y)
                    for (uint32_t x = r.x0; x <= r.x1; ++x) ++fill[t][size_t(y) * v.columns + x];
    });
    // Counts become each range's first slot in each bin.
    v.start.assign(bins + 1, 0);
    for (size_t b = 0; b < bins; ++b) {
        uint32_t at = v.start[b];
        for (uint32_t t = 0; t < threads; ++t) std::swap(at, fill[t][b]), at += fill[t][b];
        v.start[b + 1] = at;
    }
    v.ids.resize(v.start.back());
    in_ranges(n, threads, [&](uint32_t t, uint32_t begin, uint32_t end) {
        Rect r{};
        for (uint32_t i = begin; i < end; ++i) {
            const Where w = rect_of(i, r);
            if (w == Where::Always) always[t].push_back(i);
            if (w != Where::Bins) continue;
            for (uint32_t y = r.y0; y <= r.y1; ++y)
                for (uint32_t x = r.x0; x <= r.x1; ++x) v.ids[fill[t][size_t(y) * v.columns + x]++] = i;
        }
    });
    for (const auto& a : always) v.always.insert(v.always.end(), a.begin(), a.end());
    return v;
}

std::vector<uint32_t> PixelBins::candidates(const data::GaussianCloud& cloud, const data::Camera& camera, int px, int py) {
    if (px < 0 || py < 0 || px >= camera.width || py >= camera.height) return pixel_candidates(cloud, camera, px, py);
    auto it = std::find_if(views_.begin(), views_.end(), [&](const View& v) { return same_view(v.camera, camera); });
    if (it == views_.end()) {
        // A view's first click scans (binning costs a few scans); its second bins it.
        View v;
        v.camera = camera;
        views_.push_front(std::move(v));
        if (views_.size() > capacity_) views_.pop_back();
        return pixel_candidates(cloud, camera, px, py);
    }
    views_.splice(views_.begin(), views_, it);
    if (views_.front().start.empty()) views_.front() = bin(cloud, camera);
    const View& v = views_.front();
    const size_t b = size_t(py / kBin) * v.columns + size_t(px / kBin);
    std::vector<uint32_t> out;
    auto in_bin = v.ids.begin() + v.start[b], bin_end = v.ids.begin() + v.start[b + 1];
    auto all = v.always.begin();
    // The bin and the unbinned, merged in id order, each tested as the scan tests it.
    while (in_bin != bin_end || all != v.always.end()) {
        const bool from_bin = all == v.always.end() || (in_bin != bin_end && *in_bin < *all);
        const uint32_t i = from_bin ? *in_bin++ : *all++;
        if (reaches(cloud, camera, i, px, py)) out.push_back(i);
    }
    return out;
}

}  // namespace pg::seg

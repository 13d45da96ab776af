#pragma once
// Which Gaussians may reach a pixel of a view: what a click's lift draws. A scan of the whole
// cloud per click costs the scene (6 M Gaussians: ~70 ms a click on two cores), so the views
// clicked last keep their Gaussians binned by the pixels they may reach, and a further click in
// such a view tests one bin.
#include <cstdint>
#include <list>
#include <vector>

#include "dataset/camera.h"
#include "dataset/gaussian_cloud.h"

namespace pg::seg {

// The Gaussians that may reach pixel (px, py) of `camera`, in index order (a scan of the cloud).
std::vector<uint32_t> pixel_candidates(const data::GaussianCloud& cloud, const data::Camera& camera, int px, int py);

// The same answers from per-view bins of 16 x 16 pixels, for the last few views asked about. A
// view's first pixel is a scan; its second bins the view (a few scans' time, and once per cloud
// the view-independent half of every bound); later pixels cost their bin. Holds no reference
// to the cloud: the caller passes the same one each time (a new cloud needs a new PixelBins).
class PixelBins {
public:
    explicit PixelBins(size_t views = 2) : capacity_(views) {}
    std::vector<uint32_t> candidates(const data::GaussianCloud& cloud, const data::Camera& camera, int px, int py);

private:
    struct View {
        data::Camera camera;
        // Empty until the view's second pixel.
        uint32_t columns = 0, rows = 0;
        std::vector<uint32_t> start;   // per bin, where its ids begin in ids (columns x rows + 1)
        std::vector<uint32_t> ids;     // ascending within a bin
        std::vector<uint32_t> always;  // ascending: bounds too wide to bin, or not finite
    };
    void prepare(const data::GaussianCloud& cloud);
    View bin(const data::GaussianCloud& cloud, const data::Camera& camera);

    size_t capacity_;
    const data::GaussianCloud* prepared_ = nullptr;
    std::vector<glm::vec2> size_;   // per Gaussian: largest scale squared, extent2 at its opacity (< 0: too faint)
    std::list<View> views_;  // most recently used first
};

}  // namespace pg::seg

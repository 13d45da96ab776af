#pragma once
// Topological mask refinement on the GPU (paper: "Topological Mask Refinement"): multi-scale
// morphological closing, hole filling, and the largest connected component per instance, on
// an instance-label image: one uint32 per pixel, row-major, 0 = background, k >= 1 = instance
// k (ids may be sparse and any uint32 value). The stages run in this order, each on the
// previous one's result, each switchable. Exact definitions (tests/reference/mask_refine_ref
// implements the same plainly; the GPU matches it pixel for pixel):
//
// 1. Closing, for each radius r of `closing_radii` in order (r = 0 does nothing):
//      closing_k = erode_r(dilate_r(mask_k)) for every instance k of the current image, with
//      the square (Chebyshev) structuring element of radius r, i.e. the (2r+1)^2 window.
//      Border: pixels outside the image count as not-k for the dilation and as k for the
//      erosion (OpenCV's default for morphologyEx), so nothing erodes at the image border and
//      a gap of at most r pixels between an instance and the border is closed.
//    A 0-pixel that lies in closing_k of one or more k takes the smallest such k; non-zero
//    pixels never change. All closings of one radius are taken from the same image.
//    Radii above max(width, height) - 1 act like max(width, height) - 1; at most 255.
// 2. Hole filling: a hole is a 4-connected component of 0-pixels that contains no pixel of
//    the image border and whose 4-neighbours outside it all carry the same instance k; it
//    becomes k. Holes bordered by two or more instances stay 0.
// 3. Largest component: for each instance k, of its 8-connected components all but the
//    largest become 0; among equally large ones the component containing the lowest
//    row-major pixel index stays.
//
// Everything is recorded into the caller's command list, with no host wait and a fixed
// number of commands (2 per radius, about 20 for the other two stages), so a caller can time
// it with begin_pass and submit it with other work.
//  - Closing: one workgroup per tile takes the instances within r of the tile (only they can
//    claim its pixels) in ascending batches of 16, as bit rows of 64 pixels per instance in
//    shared memory (refine_close, r <= 12); any number of instances works, extra cost arises
//    only where many meet. Radii above 12 use per-pixel instance bits in global scratch
//    (refine_close_global): exact too, but on lavapipe, which stops a shader's loops after
//    65535 iterations in all, a tile with hundreds of instances within r > 12 of it could
//    exceed that. refine_close stays within it for any image.
//  - Components: union-find, tile-local in shared memory, then across tile borders; a
//    component's root is its smallest pixel index. Holes gather border contact and the
//    lowest/highest neighbouring instance at the root; the largest component per instance
//    comes from sizes summed at the roots and a hash table keyed by instance id.
#include <cstdint>
#include <string>
#include <vector>

#include "engine/vk/buffer.h"
#include "engine/vk/commands.h"

namespace pg::seg {

struct RefineOptions {
    std::vector<int> closing_radii{1, 2, 3};  // pixels; the caller scales them with image size
    bool fill_holes = true;
    bool largest_component = true;
    // Non-empty: each stage is a named GPU pass (prefix + "closing", "holes", "components"),
    // which ends any pass the caller had open. Empty: no passes are started.
    std::string pass_prefix;
};

class MaskRefiner {
public:
    explicit MaskRefiner(vk::Context& ctx);

    // Records the refinement of the width x height label image `labels_in` into `labels_out`
    // (which may be `labels_in`; otherwise `labels_in` is left unchanged). Several calls may
    // be recorded into one command list.
    void refine(vk::CommandList& cmd, const vk::Buffer& labels_in, vk::Buffer& labels_out, int width, int height,
                const RefineOptions& options = {});

private:
    void close(vk::CommandList& cmd, const vk::Buffer& src, const vk::Buffer& dst, int radius);
    void fill_holes(vk::CommandList& cmd, const vk::Buffer& src, const vk::Buffer& dst);
    void keep_largest(vk::CommandList& cmd, const vk::Buffer& src, const vk::Buffer& dst);
    // Union-find components of `labels` (mode: refine_shared.h) into parent_, and with
    // `sizes` the tile-local component sizes into aux0_.
    void components(vk::CommandList& cmd, const vk::Buffer& labels, uint32_t mode, bool sizes);
    vk::Buffer& grow(vk::Buffer& b, VkDeviceSize bytes, const char* name);

    vk::Context& ctx_;
    uint32_t width_ = 0, height_ = 0;
    vk::Buffer work_[2];        // intermediate label images
    vk::Buffer parent_;         // union-find, per pixel
    vk::Buffer aux0_, aux1_;    // per pixel: holes' lowest/highest neighbour; components' size/slot
    vk::Buffer keys_, best_size_, best_root_;  // per-instance table of the largest-component stage
    vk::Buffer scratch_;        // closing with large radii
    // Buffers replaced by bigger ones, kept alive: a recorded command list may still use them.
    std::vector<vk::Buffer> retired_;
};

}  // namespace pg::seg

#include "engine/segment/mask_refine.h"

#include <algorithm>
#include <bit>
#include <stdexcept>
#include <string>

#include "engine/vk/context.h"
#include "shaders/segment/refine_shared.h"

namespace pg::seg {

namespace {

constexpr int kMaxRadius = 255;
// Scratch of the global-memory closing variant; larger radii run in waves of tiles.
constexpr VkDeviceSize kScratchBudget = VkDeviceSize(32) << 20;

using vk::ceil_div;

}  // namespace

MaskRefiner::MaskRefiner(vk::Context& ctx) : ctx_(ctx) {}

vk::Buffer& MaskRefiner::grow(vk::Buffer& b, VkDeviceSize bytes, const char* name) {
    bytes = std::max<VkDeviceSize>(bytes, 4);
    if (b.valid() && b.size() >= bytes) return b;
    if (b.valid()) retired_.push_back(std::move(b));
    b = vk::Buffer(ctx_, bytes, vk::MemoryUse::Device, name);
    return b;
}

void MaskRefiner::refine(vk::CommandList& cmd, const vk::Buffer& labels_in, vk::Buffer& labels_out, int width,
                         int height, const RefineOptions& options) {
    if (width <= 0 || height <= 0 || uint64_t(width) * uint64_t(height) > (uint64_t(1) << 31))
        throw std::invalid_argument("mask refinement: unusable image size " + std::to_string(width) + "x" +
                                    std::to_string(height));
    const uint64_t pixels = uint64_t(width) * uint64_t(height);
    const VkDeviceSize bytes = pixels * 4;
    for (const vk::Buffer* b : {&labels_in, static_cast<const vk::Buffer*>(&labels_out)})
        if (!b->valid() || b->size() < bytes)
            throw std::invalid_argument("mask refinement: buffer '" + b->name() + "' holds fewer than the " +
                                        std::to_string(pixels) + " labels of a " + std::to_string(width) + "x" +
                                        std::to_string(height) + " image");
    std::vector<int> radii;
    for (int r : options.closing_radii) {
        if (r < 0 || r > kMaxRadius)
            throw std::invalid_argument("mask refinement: closing radius " + std::to_string(r) + " is outside 0.." +
                                        std::to_string(kMaxRadius));
        // Past max(w, h) - 1 every window already spans the image: the same closing.
        r = std::min(r, std::max(width, height) - 1);
        if (r > 0) radii.push_back(r);
    }
    width_ = uint32_t(width);
    height_ = uint32_t(height);

    const int ops = int(radii.size()) + int(options.fill_holes) + int(options.largest_component);
    if (ops == 0) {
        if (labels_in.handle() != labels_out.handle()) cmd.copy(labels_in, labels_out, bytes);
        return;
    }
    grow(work_[0], bytes, "refine labels 0");
    grow(work_[1], bytes, "refine labels 1");
    grow(parent_, bytes, "refine parent");
    grow(aux0_, bytes, "refine aux 0");
    grow(aux1_, bytes, "refine aux 1");

    // Each stage reads `cur`; the last writes labels_out. The closing cannot work in place
    // (tiles read their neighbours' pixels); the other stages' last pass is elementwise.
    const vk::Buffer* cur = &labels_in;
    int op = 0;
    auto other_work = [&] { return cur == &work_[0] ? &work_[1] : &work_[0]; };
    if (!radii.empty() && !options.pass_prefix.empty()) cmd.begin_pass(options.pass_prefix + "closing");
    for (int r : radii) {
        const bool last = ++op == ops;
        const vk::Buffer* dst = last && labels_out.handle() != cur->handle() ? &labels_out : other_work();
        close(cmd, *cur, *dst, r);
        cur = dst;
    }
    if (options.fill_holes) {
        if (!options.pass_prefix.empty()) cmd.begin_pass(options.pass_prefix + "holes");
        const bool last = ++op == ops;
        const vk::Buffer* dst = last ? &labels_out : (cur == &labels_in ? &work_[0] : cur);
        fill_holes(cmd, *cur, *dst);
        cur = dst;
    }
    if (options.largest_component) {
        if (!options.pass_prefix.empty()) cmd.begin_pass(options.pass_prefix + "components");
        const vk::Buffer* dst = &labels_out;
        keep_largest(cmd, *cur, *dst);
        cur = dst;
    }
    // Only when a closing came last and labels_out is labels_in.
    if (cur->handle() != labels_out.handle()) cmd.copy(*cur, labels_out, bytes);
    if (!options.pass_prefix.empty()) cmd.end_pass();
}

void MaskRefiner::close(vk::CommandList& cmd, const vk::Buffer& src, const vk::Buffer& dst, int radius) {
    const uint32_t r = uint32_t(radius);
    gpu::ClosePush push{width_, height_, r, 0, 0, 0, 0, 0};
    const int shared_tile = PG_CLOSE_REGION - 4 * radius;
    if (shared_tile >= PG_CLOSE_MIN_TILE) {
        push.tile = uint32_t(shared_tile);
        push.tiles_x = uint32_t(ceil_div(width_, push.tile));
        push.tile_count = push.tiles_x * uint32_t(ceil_div(height_, push.tile));
        cmd.copy(src, dst, VkDeviceSize(width_) * height_ * 4);  // the kernel writes what changes
        cmd.dispatch("segment/refine_close", {src, dst}, push, push.tile_count);
        return;
    }
    // Large radius: the region's arrays live in global scratch, one slice per workgroup.
    push.tile = std::max<uint32_t>(PG_CLOSE_GLOBAL_TILE, 4 * r);
    push.tiles_x = uint32_t(ceil_div(width_, push.tile));
    push.tile_count = push.tiles_x * uint32_t(ceil_div(height_, push.tile));
    const uint32_t region = push.tile + 4 * r;
    push.scratch_words = region * region + region * (push.tile + 2 * r);
    const VkDeviceSize slice = VkDeviceSize(push.scratch_words) * 4;
    const uint32_t wave = uint32_t(std::clamp<VkDeviceSize>(kScratchBudget / slice, 1, push.tile_count));
    vk::Buffer& scratch = grow(scratch_, slice * wave, "refine closing scratch");
    for (uint32_t base = 0; base < push.tile_count; base += wave) {
        push.tile_base = base;
        cmd.dispatch("segment/refine_close_global", {src, dst, scratch}, push,
                     std::min(wave, push.tile_count - base));
    }
}

void MaskRefiner::components(vk::CommandList& cmd, const vk::Buffer& labels, uint32_t mode, bool sizes) {
    const gpu::CcPush push{width_, height_, mode, sizes ? 1u : 0u};
    const uint32_t tiles_x = uint32_t(ceil_div(width_, PG_CC_TILE)), tiles_y = uint32_t(ceil_div(height_, PG_CC_TILE));
    if (sizes) cmd.fill(aux0_, 0u, 0, VkDeviceSize(width_) * height_ * 4);  // written at tile-local roots only
    cmd.dispatch_2d("segment/refine_cc_local", {labels, parent_, aux0_}, push, tiles_x, tiles_y);
    cmd.dispatch_2d("segment/refine_cc_edges", {labels, parent_}, push, tiles_x, tiles_y);
    cmd.dispatch("segment/refine_cc_compress", {parent_}, push,
                 ceil_div(uint64_t(width_) * height_, PG_REFINE_THREADS));
}

void MaskRefiner::fill_holes(vk::CommandList& cmd, const vk::Buffer& src, const vk::Buffer& dst) {
    const uint64_t pixels = uint64_t(width_) * height_;
    const uint64_t groups = ceil_div(pixels, PG_REFINE_THREADS);
    components(cmd, src, PG_CC_ZERO_4, false);
    cmd.fill(aux0_, 0xFFFFFFFFu, 0, pixels * 4);  // lowest neighbouring instance; 0 = touches the border
    cmd.fill(aux1_, 0u, 0, pixels * 4);           // highest neighbouring instance
    const gpu::PixelPush push{width_, height_, 0, 0};
    cmd.dispatch("segment/refine_hole_gather", {src, parent_, aux0_, aux1_}, push, groups);
    cmd.dispatch("segment/refine_hole_apply", {src, dst, parent_, aux0_, aux1_}, push, groups);
}

void MaskRefiner::keep_largest(vk::CommandList& cmd, const vk::Buffer& src, const vk::Buffer& dst) {
    const uint64_t pixels = uint64_t(width_) * height_;
    const uint64_t groups = ceil_div(pixels, PG_REFINE_THREADS);
    // One slot per instance; never fuller than the pixel count, so probing always ends.
    const uint64_t slots = std::bit_ceil(pixels);
    grow(keys_, slots * 4, "refine instance keys");
    grow(best_size_, slots * 4, "refine instance best size");
    grow(best_root_, slots * 4, "refine instance best root");
    cmd.fill(keys_, 0u, 0, slots * 4);
    cmd.fill(best_size_, 0u, 0, slots * 4);
    cmd.fill(best_root_, 0xFFFFFFFFu, 0, slots * 4);
    components(cmd, src, PG_CC_LABEL_8, true);  // tile-local sizes in aux0_
    const gpu::PixelPush push{width_, height_, uint32_t(slots - 1), 0};
    cmd.dispatch("segment/refine_lcc_count", {parent_, aux0_}, push, groups);
    cmd.dispatch("segment/refine_lcc_insert", {src, parent_, aux0_, aux1_, keys_, best_size_}, push, groups);
    cmd.dispatch("segment/refine_lcc_tie", {src, parent_, aux0_, aux1_, best_size_, best_root_}, push, groups);
    cmd.dispatch("segment/refine_lcc_apply", {src, dst, parent_, aux1_, best_root_}, push, groups);
}

}  // namespace pg::seg

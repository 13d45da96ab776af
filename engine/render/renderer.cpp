#include "engine/render/renderer.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "engine/render/slab_order.h"
#include "engine/vk/context.h"
#include "shaders/common/common_shared.h"
#include "shaders/render/render_shared.h"

namespace pg::render {

namespace {

gpu::FrameParams frame_params(const data::Camera& cam, const RenderSettings& s, uint32_t count, uint32_t sh_words,
                              int sh_degree, uint32_t capacity, uint32_t group_limit, uint32_t palette_size) {
    gpu::FrameParams f{};
    glm::dmat4 view = cam.world_to_camera();
    f.view = glm::mat4(view);
    f.camera_pos = glm::vec4(glm::vec3(cam.position()), 1.0f);
    f.intrinsics = glm::vec4(float(cam.fx), float(cam.fy), float(cam.cx), float(cam.cy));
    f.background = glm::vec4(s.background, s.tau);
    f.clip = glm::vec4(s.near, float(0.5 * cam.width / cam.fx), float(0.5 * cam.height / cam.fy), 0.0f);
    uint32_t tiles_x = vk::ceil_div(uint32_t(cam.width), gpu::kTileSize);
    uint32_t tiles_y = vk::ceil_div(uint32_t(cam.height), gpu::kTileSize);
    f.size = glm::uvec4(cam.width, cam.height, tiles_x, tiles_y);
    f.scene = glm::uvec4(count, sh_words, uint32_t(std::clamp(std::min(sh_degree, s.max_sh_degree), 0, 3)),
                         s.antialiased ? 1u : 0u);
    f.capacity = glm::uvec4(capacity, group_limit, palette_size, 0);
    const glm::ivec4& w = s.window;
    f.window = glm::uvec4(0, 0, cam.width, cam.height);
    if (w.z > w.x && w.w > w.y)
        f.window = glm::uvec4(glm::clamp(glm::ivec4(w), glm::ivec4(0), glm::ivec4(cam.width, cam.height, cam.width, cam.height)));
    return f;
}

void check_style(const RenderStyle& style, uint32_t count) {
    if (!style.labels || !style.palette || style.palette_size == 0)
        throw std::invalid_argument("render style needs a labels buffer, a palette buffer and a palette size > 0");
    if (style.labels->size() < uint64_t(count) * 4)
        throw std::invalid_argument("render style labels buffer '" + style.labels->name() + "' holds " +
                                    std::to_string(style.labels->size()) + " bytes, fewer than one int32 for each of " +
                                    std::to_string(count) + " Gaussians");
    if (style.palette->size() < uint64_t(style.palette_size) * 16)
        throw std::invalid_argument("render style palette buffer '" + style.palette->name() + "' holds " +
                                    std::to_string(style.palette->size()) + " bytes, fewer than " +
                                    std::to_string(style.palette_size) + " vec4 entries");
}

}  // namespace

Renderer::Renderer(vk::Context& ctx)
    : ctx_(ctx),
      cmd_(ctx),
      scan_(ctx),
      sort_(ctx),
      frame_(ctx, sizeof(gpu::FrameParams), vk::MemoryUse::Device, "frame params"),
      counters_(ctx, 16, vk::MemoryUse::Device, "render counters"),
      args_(ctx, 16, vk::MemoryUse::Device, "render indirect args"),
      no_style_(ctx, 16, vk::MemoryUse::Device, "no render style"),
      pick_(ctx, sizeof(gpu::PixelPick), vk::MemoryUse::Device, "pixel pick"),
      pick_state_(ctx, 2 * gpu::kPickWalkWords * 4, vk::MemoryUse::Device, "pixel pick walks"),
      slab_(ctx, "render slab") {}

void Renderer::render(const GpuScene& scene, const data::Camera& camera_in, const RenderSettings& settings,
                      const RenderStyle* style, const SlabHook& after_slab) {
    data::Camera camera = camera_in;
    if (settings.width > 0 && settings.height > 0) camera = camera_in.resized(settings.width, settings.height);
    if (camera.width <= 0 || camera.height <= 0 || camera.width > 16384 || camera.height > 16384)
        throw std::runtime_error("camera '" + camera.name + "' has an unusable image size " +
                                 std::to_string(camera.width) + "x" + std::to_string(camera.height));
    width_ = camera.width;
    height_ = camera.height;
    last_scene_ = &scene;
    blend_kernel_ = settings.blend_kernel != BlendKernel::Auto ? settings.blend_kernel
                    : ctx_.info().type == VK_PHYSICAL_DEVICE_TYPE_CPU ? BlendKernel::Column
                                                                      : BlendKernel::Pixel;
    if (style) check_style(*style, scene.size());

    if (!splats_.valid()) {
        splats_ = vk::Buffer(ctx_, 0, vk::MemoryUse::Device, "splats");
        touched_ = vk::Buffer(ctx_, 0, vk::MemoryUse::Device, "tiles touched");
        offsets_ = vk::Buffer(ctx_, 0, vk::MemoryUse::Device, "key offsets");
        rects_ = vk::Buffer(ctx_, 0, vk::MemoryUse::Device, "tile rects");
        depth_keys_ = vk::Buffer(ctx_, 0, vk::MemoryUse::Device, "depth keys");
        order_ = vk::Buffer(ctx_, 0, vk::MemoryUse::Device, "depth order");
        touched_sorted_ = vk::Buffer(ctx_, 0, vk::MemoryUse::Device, "tiles touched in depth order");
        keys_ = vk::Buffer(ctx_, 0, vk::MemoryUse::Device, "tile keys");
        values_ = vk::Buffer(ctx_, 0, vk::MemoryUse::Device, "sort values");
        ranges_ = vk::Buffer(ctx_, 0, vk::MemoryUse::Device, "tile ranges");
        image_ = vk::Buffer(ctx_, 0, vk::MemoryUse::Device, "image");
        aux_ = vk::Buffer(ctx_, 0, vk::MemoryUse::Device, "aux image");
    }
    const uint64_t pixels = uint64_t(width_) * uint64_t(height_);
    image_.ensure(pixels * 16);
    aux_.ensure(pixels * 16);
    retries_ = 0;
    key_count_ = 0;
    timings_.clear();
    slabs_ = 0;
    if (!scene.streamed()) {
        render_slab(scene, camera, settings, style, scene.size(), gpu::kBlendFinal, after_slab);
        return;
    }

    // Streamed: the Gaussians in front of the camera, in depth order, cut into slabs; each slab
    // is blended over the state the slab before left, so the frame is the in-memory one.
    const auto order = slab_order(scene.cloud(), camera, settings);
    slab_host_ids_.clear();
    if (order.empty()) {
        render_slab(scene, camera, settings, style, 0, gpu::kBlendFinal, after_slab);
        return;
    }
    if (!slab_ids_.valid()) {
        slab_ids_ = vk::Buffer(ctx_, 0, vk::MemoryUse::Device, "slab ids");
        slab_labels_ = vk::Buffer(ctx_, 0, vk::MemoryUse::Device, "slab labels");
        for (int c = 0; c < 2; ++c) carry_[c] = vk::Buffer(ctx_, 0, vk::MemoryUse::Device, "blend carry");
    }
    for (auto& c : carry_) c.ensure(pixels * gpu::kCarryWords * 4);
    const uint32_t capacity = scene.slab_capacity();
    slab_ids_.ensure(uint64_t(capacity) * 4);
    std::vector<uint32_t>& ids = slab_host_ids_;  // kept: pick maps the last slab's ids back
    size_t room = capacity;  // halved while a slab's tile keys would not fit a binding
    for (size_t begin = 0; begin < order.size();) {
        size_t end = std::min(order.size(), begin + room);
        // Gaussians of equal depth stay in one slab, so their order is the in-memory one.
        while (end < order.size() && end > begin + 1 && order[end].first == order[end - 1].first) --end;
        ids.resize(end - begin);
        for (size_t k = begin; k < end; ++k) ids[k - begin] = order[k].second;
        slab_.load(scene, ids);
        vk::upload(ctx_, slab_ids_, ids.data(), ids.size() * 4);
        uint32_t flags = gpu::kBlendSlabIds;
        if (begin > 0) flags |= gpu::kBlendResume;
        if (end == order.size()) flags |= gpu::kBlendFinal;
        if (!render_slab(scene, camera, settings, style, uint32_t(ids.size()), flags, after_slab)) {
            room = std::max<size_t>(1, (end - begin) / 2);
            continue;  // the carry it read is untouched: the smaller slab starts from it again
        }
        begin = end;
    }
}

bool Renderer::render_slab(const GpuScene& scene, const data::Camera& camera, const RenderSettings& settings,
                           const RenderStyle* style, uint32_t n, uint32_t flags, const SlabHook& after_slab) {
    const uint32_t tiles_x = vk::ceil_div(uint32_t(width_), gpu::kTileSize);
    const uint32_t tiles_y = vk::ceil_div(uint32_t(height_), gpu::kTileSize);
    const uint32_t tiles = tiles_x * tiles_y;
    const bool slab = (flags & gpu::kBlendSlabIds) != 0;
    const vk::Buffer& means = slab ? slab_.means : scene.means;
    const vk::Buffer& shapes = slab ? slab_.shapes : scene.shapes;
    const vk::Buffer& sh = slab ? slab_.sh : scene.sh;
    const vk::Buffer* labels = style ? style->labels : &no_style_;
    const vk::Buffer& palette = style ? *style->palette : no_style_;
    const uint32_t palette_size = style ? style->palette_size : 0;

    splats_.ensure(uint64_t(n) * sizeof(gpu::Splat));
    touched_.ensure(uint64_t(n) * 4);
    offsets_.ensure(uint64_t(n) * 4);
    rects_.ensure(uint64_t(n) * 8);
    depth_keys_.ensure(uint64_t(n) * 4);
    order_.ensure(uint64_t(n) * 4);
    touched_sorted_.ensure(uint64_t(n) * 4);
    ranges_.ensure(uint64_t(tiles) * 8);
    if (capacity_ == 0) capacity_ = std::max<uint32_t>(1024, std::min<uint64_t>(uint64_t(n) * 4, 1u << 24));
    // A slab's carry: read from one buffer, written to the other, so a retried slab starts over.
    const vk::Buffer& carry_in = slab ? carry_[slabs_ % 2] : no_style_;
    const vk::Buffer& carry_out = slab ? carry_[(slabs_ + 1) % 2] : no_style_;
    const vk::Buffer& ids = slab ? slab_ids_ : no_style_;

    const uint32_t tile_bits = std::max(1, int(std::bit_width(tiles)));  // tile ids 0..tiles (padding)
    const uint32_t group_limit = ctx_.max_group_count_x();
    for (int tries = 0;; ++tries) {
        keys_.ensure(uint64_t(capacity_) * 4);
        values_.ensure(uint64_t(capacity_) * 4);
        auto params = frame_params(camera, settings, n, scene.sh_words(), scene.sh_degree(), capacity_, group_limit,
                                   palette_size);
        const glm::uvec4 win = params.window;
        const bool one_tile = win.z > win.x && win.w > win.y && win.x / gpu::kTileSize == (win.z - 1) / gpu::kTileSize &&
                              win.y / gpu::kTileSize == (win.w - 1) / gpu::kTileSize;
        params.capacity.w = flags | (scene.half_sh() ? gpu::kFrameHalfSh : 0u) | (one_tile ? gpu::kFrameDepthKeys : 0u);
        cmd_.update(frame_, &params, sizeof(params));
        if (style && slab) {
            // The slab's labels, gathered from the scene's by the slab's ids.
            slab_labels_.ensure(std::max<uint64_t>(uint64_t(n) * 4, 16));
            cmd_.dispatch("render/gather_labels", {ids, *style->labels, slab_labels_}, gpu::GatherPush{{n, 0, 0, 0}},
                          vk::ceil_div(n, 256));
            labels = &slab_labels_;
        }
        cmd_.begin_pass("preprocess");
        cmd_.dispatch("render/preprocess", {frame_, means, shapes, sh, splats_, touched_, rects_,
                                            depth_keys_, order_, *labels, palette},
                      vk::ceil_div(n, 256));
        // Two stable sorts give the tile-major, front-to-back order of a 64-bit tile|depth sort
        // with about half the work: Gaussians by depth once, then keys by tile id alone.
        // One tile's list needs no sort of every Gaussian: its few keys are sorted by depth below.
        if (!one_tile) {
            cmd_.begin_pass("depth sort");
            sort_.sort(cmd_, depth_keys_, order_, n, 32, sort::KeyWidth::Bits32);
        }
        cmd_.begin_pass("scan");
        cmd_.dispatch("render/gather_touched", {frame_, order_, touched_, touched_sorted_}, vk::ceil_div(n, 256));
        scan_.exclusive(cmd_, touched_sorted_, offsets_, n, &counters_, 0);
        cmd_.begin_pass("emit");
        cmd_.dispatch("render/emit_keys", {frame_, splats_, order_, touched_sorted_, offsets_, rects_, keys_, values_},
                      vk::ceil_div(n, 256));
        cmd_.begin_pass("tile sort");
        sort_.sort_indirect(cmd_, keys_, values_, counters_, 0, capacity_, one_tile ? 32 : tile_bits,
                            sort::KeyWidth::Bits32);
        cmd_.begin_pass("ranges");
        cmd_.fill(ranges_, 0);
        const vk::gpu::IndirectArgsPush args{0, 256, group_limit, 0, capacity_};
        cmd_.dispatch("common/indirect_args", {counters_, args_}, args, 1);
        cmd_.dispatch_indirect("render/tile_ranges", {frame_, counters_, keys_, ranges_}, args_);
        cmd_.fill(counters_, 0, 4, 4);
        cmd_.dispatch("render/tile_longest", {frame_, ranges_, counters_}, vk::ceil_div(tiles, 256));
        // A frame of at most kTileWindow Gaussians cannot hold more keys in one tile; a larger one
        // plans with the last frame's longest list and is drawn again below if that was short.
        windows_ = n <= gpu::kTileWindow ? 1 : std::max<uint32_t>(1, vk::ceil_div(longest_tile_, gpu::kTileWindow));
        if (!settings.lists_only) record_tile_passes(n, flags, carry_in, carry_out, after_slab);
        cmd_.submit_and_wait();
        add_timings();
        const auto counts = vk::download_vector<uint32_t>(ctx_, counters_, 2);
        const uint32_t keys = counts[0];
        if (keys <= capacity_) {
            key_count_ += keys;
            longest_tile_ = counts[1];
            const uint32_t needed = std::max<uint32_t>(1, vk::ceil_div(longest_tile_, gpu::kTileWindow));
            if (needed > windows_) {
                windows_ = needed;
                if (!settings.lists_only) {
                    record_tile_passes(n, flags, carry_in, carry_out, after_slab);
                    cmd_.submit_and_wait();
                    add_timings();
                }
            }
            break;
        }
        ++retries_;
        if (tries >= 3) throw std::runtime_error("renderer: key buffer kept overflowing");
        uint64_t grown = uint64_t(keys) + keys / 4;
        const uint64_t max_keys = scene.binding_limit() / 8;
        if (uint64_t(keys) > max_keys && slab && n > 1) return false;
        if (uint64_t(keys) > max_keys)
            throw std::runtime_error("frame needs " + std::to_string(keys) + " tile keys, more than the device can bind (" +
                                     std::to_string(max_keys) + "); render at a lower resolution");
        capacity_ = uint32_t(std::min(grown, max_keys));
    }
    ++slabs_;
    return true;
}

void Renderer::record_tile_passes(uint32_t n, uint32_t flags, const vk::Buffer& carry_in, const vk::Buffer& carry_out,
                                  const SlabHook& after_slab) {
    const bool slab = (flags & gpu::kBlendSlabIds) != 0;
    const vk::Buffer& ids = slab ? slab_ids_ : no_style_;
    if (windows_ > 1)
        for (auto& w : window_carry_) {
            if (!w.valid()) w = vk::Buffer(ctx_, 0, vk::MemoryUse::Device, "blend window carry");
            w.ensure(uint64_t(width_) * uint64_t(height_) * gpu::kCarryWords * 4);
        }
    cmd_.begin_pass("blend");
    for (uint32_t w = 0; w < windows_; ++w) {
        const vk::Buffer& window_in = windows_ > 1 ? window_carry_[w % 2] : no_style_;
        const vk::Buffer& window_out = windows_ > 1 ? window_carry_[(w + 1) % 2] : no_style_;
        const bool four = blend_kernel_ == BlendKernel::Column;  // render/blend built with PG_RUN_ROWS 4
        const char* kernel = windows_ > 1 ? (four ? "render/blend_windows_rows4" : "render/blend_windows_rows1")
                                          : (four ? "render/blend_rows4" : "render/blend_rows1");
        cmd_.dispatch_2d(kernel,
                         {frame_, splats_, values_, ranges_, image_, aux_, ids, carry_in, carry_out, window_in, window_out},
                         gpu::TileWindowPush{{w, windows_, 0, 0}}, tiles_x(), tiles_y());
    }
    if (after_slab) after_slab(cmd_, SlabPass{uint32_t(slabs_), n, flags, slab ? &slab_ids_ : nullptr, windows_});
    cmd_.end_pass();
}

void Renderer::add_timings() {
    for (auto& t : cmd_.timings()) {
        auto it = std::find_if(timings_.begin(), timings_.end(), [&](auto& u) { return u.name == t.name; });
        if (it == timings_.end()) timings_.push_back(t);
        else it->ms += t.ms;
    }
}

uint32_t Renderer::tiles_x() const { return vk::ceil_div(uint32_t(width_), gpu::kTileSize); }
uint32_t Renderer::tiles_y() const { return vk::ceil_div(uint32_t(height_), gpu::kTileSize); }

PixelPick Renderer::pick(int x, int y) {
    if (!last_scene_) throw std::logic_error("Renderer::pick: nothing was rendered");
    const bool streamed = last_scene_->streamed();
    if (streamed && slabs_ > 1)
        throw std::runtime_error("picking a pixel of a streamed scene needs a frame of one slab; this one took " +
                                 std::to_string(slabs_) + " (render a window around the pixel)");
    if (x < 0 || y < 0 || x >= width_ || y >= height_)
        throw std::out_of_range("Renderer::pick: pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                                ") is off the " + std::to_string(width_) + "x" + std::to_string(height_) + " frame");
    // Both walks, window by window: the first finds the dominant surface, the second its median
    // and the tau Gaussian.
    for (uint32_t walk = 0; walk < 2; ++walk)
        for (uint32_t w = 0; w < windows_; ++w)
            cmd_.dispatch("render/pick_pixel",
                          {frame_, splats_, values_, ranges_, streamed ? slab_.shapes : last_scene_->shapes, pick_, pick_state_},
                          gpu::PickPush{{uint32_t(x), uint32_t(y), w, walk}, {windows_, 0, 0, 0}}, 1);
    cmd_.submit_and_wait();
    const auto g = vk::download_vector<gpu::PixelPick>(ctx_, pick_, 1)[0];
    PixelPick p;
    auto scene_id = [&](uint32_t id) {
        if (id == gpu::kNoGaussian) return -1;
        return int32_t(streamed ? slab_host_ids_.at(id) : id);
    };
    p.surface_id = scene_id(g.ids.x);
    p.tau_id = scene_id(g.ids.y);
    p.surface_depth = g.depths.x;
    p.tau_depth = g.depths.y;
    p.surface_weight = g.weights.x;
    p.opacity = g.weights.y;
    p.tau = g.weights.z;
    return p;
}

RenderImages Renderer::read() const {
    RenderImages out;
    out.width = width_;
    out.height = height_;
    const size_t pixels = size_t(width_) * size_t(height_);
    out.rgba = vk::download_vector<float>(ctx_, image_, pixels * 4);
    auto aux = vk::download_vector<glm::uvec4>(ctx_, aux_, pixels);
    out.depth.resize(pixels);
    out.tau_depth.resize(pixels);
    out.tau_id.resize(pixels);
    out.contributors.resize(pixels);
    for (size_t p = 0; p < pixels; ++p) {
        out.depth[p] = std::bit_cast<float>(aux[p].x);
        out.tau_depth[p] = std::bit_cast<float>(aux[p].y);
        out.tau_id[p] = aux[p].z == gpu::kNoGaussian ? -1 : int32_t(aux[p].z);
        out.contributors[p] = aux[p].w;
    }
    return out;
}

}  // namespace pg::render

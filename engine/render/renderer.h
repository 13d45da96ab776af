#pragma once
// The tile-based 3DGS splat renderer: preprocess -> depth sort -> prefix sum -> key emission ->
// tile sort -> tile ranges -> blend, recorded into one command list with no host round trip between
// passes. If the keys overflow their buffer the frame is rendered again with larger ones. A
// streamed scene is drawn slab by slab, front to back, each blended over the last.
#include <cstdint>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "dataset/camera.h"
#include "engine/render/gpu_scene.h"
#include "engine/sort/prefix_sum.h"
#include "engine/sort/radix_sort.h"
#include "engine/vk/commands.h"

namespace pg::render {

// How many pixels of a tile's column one invocation of the blend (and of the occlusion label
// pass that walks the same lists) draws. Column: four for the blend, two for the label pass,
// which holds more state per pixel. Auto: Column on CPU Vulkan devices (lavapipe loads shared
// memory lane by lane, so the pixels of a column share each splat's loads: blend about 0.55x,
// labels 0.8x), one pixel elsewhere. Both give the same images; the tests run both.
enum class BlendKernel { Auto, Pixel, Column };

struct RenderSettings {
    int width = 0, height = 0;     // 0: the camera's own size (intrinsics scale with it)
    glm::vec3 background{0.0f};
    float tau = 0.9f;              // opacity at which the tau-depth and picking id are taken
    bool antialiased = false;      // Mip-Splatting opacity compensation
    int max_sh_degree = 3;
    float near = 0.2f;
    // Pixels x0, y0 (inclusive) to x1, y1 (exclusive) the frame must draw: everything that cannot
    // reach them is culled (a streamed scene's slabs too), and other pixels may hold anything.
    // Empty (x1 <= x0): the whole image. A click's lift draws its pixel alone.
    glm::ivec4 window{0};
    // Bin the Gaussians into tile lists and skip the blend (and the slab hook): the image outputs
    // hold anything, but pick() and passes that walk the lists (tile_values, tile_ranges) work.
    bool lists_only = false;
    BlendKernel blend_kernel = BlendKernel::Auto;
};

// An optional per-Gaussian look for viewers: each Gaussian's label picks a palette entry whose
// rgb is mixed into its colour by a (0: untouched, 1: flat colour); a < 0 hides the Gaussian.
struct RenderStyle {
    const vk::Buffer* labels = nullptr;   // int32 per Gaussian (0: unlabelled)
    const vk::Buffer* palette = nullptr;  // vec4 per label: rgb, a
    uint32_t palette_size = 0;            // labels < 0 or >= palette_size use palette[0]
};

// Host copies of a frame's outputs; pixels row-major, top row first.
struct RenderImages {
    int width = 0, height = 0;
    std::vector<float> rgba;                 // 4 per pixel: colour over the background, alpha
    std::vector<float> depth;                // expected view-space depth (0 where empty)
    std::vector<float> tau_depth;            // depth where accumulated opacity first reaches tau, else 0
    std::vector<int32_t> tau_id;             // Gaussian index there, -1 if never reached
    std::vector<uint32_t> contributors;      // Gaussians blended into the pixel
};

// Where one pixel of a frame lands in depth (see Renderer::pick).
struct PixelPick {
    // The pixel's dominant surface (its contributors split where they are apart in depth; the
    // surface of largest summed weight alpha * T) and its weighted median, the Gaussian at which
    // the surface's running weight reaches half its total; -1: none.
    int32_t surface_id = -1;
    float surface_depth = 0;  // that Gaussian's view-space depth
    float surface_weight = 0; // the surface's summed weight
    int32_t tau_id = -1;      // the Gaussian at which the accumulated opacity first reaches `tau`
    float tau_depth = 0;
    float tau = 0;            // the settings' tau, or tau x opacity when the pixel never reached it
    float opacity = 0;        // the pixel's final opacity 1 - T
};

// One slab of a streamed frame, as a SlabHook sees it: its tile lists are the renderer's until
// the next slab. `ids` holds the slab's scene ids (slab Gaussian i is scene Gaussian ids[i]);
// flags are gpu::kBlend* (resume from the last slab's carry, or final).
struct SlabPass {
    uint32_t index = 0, size = 0, flags = 0;
    const vk::Buffer* ids = nullptr;
    uint32_t windows = 1;  // windows of kTileWindow keys the slab's tile lists are walked in
};
// Records a pass that walks each slab's tile lists (label rasterization) into the frame's
// command list, right after the slab's blend. It may be recorded twice for one slab (when
// the tile lists need more windows than planned), so it must only write what it reads from.
using SlabHook = std::function<void(vk::CommandList&, const SlabPass&)>;

class Renderer {
public:
    explicit Renderer(vk::Context& ctx);

    // Renders one frame on the GPU and waits for it; outputs stay on the device until read().
    void render(const GpuScene& scene, const data::Camera& camera, const RenderSettings& settings,
                const RenderStyle* style = nullptr, const SlabHook& after_slab = {});
    RenderImages read() const;
    // Pixel (x, y) of the last frame, walked on the device as the blend walked it; waits for it.
    // The last frame's scene must still be alive; a streamed scene's frame must have been one
    // slab (render it with a window around the pixel).
    PixelPick pick(int x, int y);
    // The last frame's scene is gone (a caller's own short-lived scene): pick() refuses until
    // the next frame instead of reading freed buffers.
    void forget_scene() { last_scene_ = nullptr; }

    vk::Context& context() const { return ctx_; }
    const std::vector<vk::PassTiming>& timings() const { return timings_; }
    uint32_t key_count() const { return key_count_; }
    int retries() const { return retries_; }
    int slabs() const { return slabs_; }
    bool streamed() const { return last_scene_ && last_scene_->streamed(); }  // the last frame's scene  // slabs the last frame was drawn in (1: resident scene)
    int width() const { return width_; }
    int height() const { return height_; }
    // Device outputs, for passes that consume a frame without reading it back.
    const vk::Buffer& image_buffer() const { return image_; }  // vec4 per pixel
    const vk::Buffer& aux_buffer() const { return aux_; }      // uvec4: depth, tau-depth bits, tau id, contributors
    // The last frame's binning, for passes that walk the same per-tile lists (label rasterization).
    const vk::Buffer& frame_buffer() const { return frame_; }  // gpu::FrameParams
    const vk::Buffer& splat_buffer() const { return splats_; } // gpu::Splat per Gaussian (valid where it touches a tile)
    const vk::Buffer& tile_values() const { return values_; }  // Gaussian ids, tile-major, front to back
    const vk::Buffer& tile_ranges() const { return ranges_; }  // uvec2 [start, end) into tile_values() per tile
    // Windows of gpu::kTileWindow keys that cover the longest tile list of the last frame (or
    // slab): passes that walk the lists take one window per dispatch.
    uint32_t tile_windows() const { return windows_; }
    BlendKernel blend_kernel() const { return blend_kernel_; }  // the last frame's, Auto resolved
    uint32_t tiles_x() const;
    uint32_t tiles_y() const;

private:
    // Records and runs one frame (or one slab of a streamed scene) over the first n Gaussians
    // in the scene's device buffers; flags: gpu::kBlend*. False: the slab's tile keys cannot
    // fit one binding (draw fewer Gaussians at a time).
    bool render_slab(const GpuScene& scene, const data::Camera& camera, const RenderSettings& settings,
                     const RenderStyle* style, uint32_t n, uint32_t flags, const SlabHook& after_slab);
    // The blend's windows_ dispatches and the slab hook.
    void record_tile_passes(uint32_t n, uint32_t flags, const vk::Buffer& carry_in, const vk::Buffer& carry_out,
                            const SlabHook& after_slab);
    void add_timings();

    vk::Context& ctx_;
    vk::CommandList cmd_;
    sort::PrefixSum scan_;
    sort::RadixSort sort_;
    vk::Buffer frame_, splats_, touched_, offsets_, rects_, counters_, args_, keys_, values_, ranges_, image_, aux_;
    vk::Buffer depth_keys_, order_, touched_sorted_;
    vk::Buffer no_style_;
    vk::Buffer pick_;      // one gpu::PixelPick
    vk::Buffer pick_state_;  // the pick's two walks between windows
    vk::Buffer window_carry_[2];  // pixel state between windows of the tile lists
    uint32_t windows_ = 1, longest_tile_ = 0;
    BlendKernel blend_kernel_ = BlendKernel::Pixel;  // this frame's, resolved
    vk::Buffer slab_ids_, slab_labels_, carry_[2];  // streamed scenes only
    std::vector<uint32_t> slab_host_ids_;           // the last slab's scene ids
    SceneSlab slab_;
    const GpuScene* last_scene_ = nullptr;  // the scene of the last frame (pick reads its shapes)  // bound as labels and palette when a frame has no style
    uint32_t capacity_ = 0, key_count_ = 0;
    int width_ = 0, height_ = 0, retries_ = 0, slabs_ = 0;
    std::vector<vk::PassTiming> timings_;
};

}  // namespace pg::render

// Layouts and constants shared by the splat renderer's C++ and GLSL: one definition, no drift.
// Only vec4/mat4/uvec4-aligned members, so std430 and C++ agree byte for byte.
#ifndef PG_RENDER_SHARED_H
#define PG_RENDER_SHARED_H

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
namespace pg::render::gpu {
using vec2 = glm::vec2;
using vec4 = glm::vec4;
using uvec2 = glm::uvec2;
using uvec4 = glm::uvec4;
using mat4 = glm::mat4;
using uint = uint32_t;
#define PG_CONST inline constexpr
#else
#define PG_CONST const
#endif

PG_CONST uint kTileSize = 16;
PG_CONST uint kBlendGroup = kTileSize * kTileSize;  // one thread per pixel of a tile
PG_CONST float kAlphaMax = 0.99;                    // opacity clamp of the 3DGS model
PG_CONST float kAlphaMin = 1.0 / 255.0;             // contributions below are skipped
PG_CONST float kTransmittanceMin = 0.0001;          // a pixel stops here
PG_CONST float kLowPass = 0.3;                      // added to the 2D covariance diagonal
PG_CONST float kFovClamp = 1.3;                     // Jacobian clamp, in units of tan(fov/2)
PG_CONST uint kNoGaussian = 0xFFFFFFFFu;
// A streamed scene is blended slab by slab, front to back: each slab but the first starts from
// the pixel state the one before left (carry), each but the last leaves its state there, and
// a slab's Gaussian ids map to scene ids through its id list.
PG_CONST uint kBlendResume = 1u;
PG_CONST uint kBlendFinal = 2u;
PG_CONST uint kBlendSlabIds = 4u;
// Frame flag beside the blend flags: SH coefficients are fp16 pairs (packHalf2x16 words).
PG_CONST uint kFrameHalfSh = 8u;
// The window lies in one tile: keys are view depths (emit_keys) sorted once, with no depth sort of
// all Gaussians before, and that tile's run is all of them (tile_ranges). A click's lift.
PG_CONST uint kFrameDepthKeys = 16u;
PG_CONST uint kCarryWords = 12u;  // uints per pixel of carried state
PG_CONST uint kLabelCarryWords = 20u;  // the same for the label rasterizers
// Passes that walk a tile's list (blend, the label rasterizers, pick) take at most kTileWindow
// of its keys per dispatch and carry the pixel state to the next window, as slabs do:
// lavapipe silently cuts an invocation's long loops short (a blend tile of 170 k unsaturated
// keys drew garbage, 150 k did not), and a tile of a real-size scene can hold hundreds of
// thousands of keys. A window costs each pixel at most kTileWindow / 256 batches of <= 545
// loop iterations.
PG_CONST uint kTileWindow = 16384u;
// A pixel's contributors that are further apart in depth than this x the sum of their
// standard deviations along the ray lie on different surfaces: their 3-sigma supports do not
// meet (render/pick_pixel.comp).
PG_CONST float kSurfaceGap = 3.0;

// Per-frame parameters, in a small storage buffer every pass reads.
struct FrameParams {
    mat4 view;          // world to camera (OpenCV axes)
    vec4 camera_pos;    // xyz: camera centre in world
    vec4 intrinsics;    // fx, fy, cx, cy in pixels
    vec4 background;    // rgb, w: tau (opacity at which the tau-depth is taken)
    vec4 clip;          // x: near plane, y: tan(fov_x/2), z: tan(fov_y/2), w: unused
    uvec4 size;         // width, height, tiles_x, tiles_y
    uvec4 scene;        // gaussian count, SH words per Gaussian (floats, or fp16 pairs), SH degree used, antialiased
    uvec4 capacity;     // x: key capacity, y: device group-count limit, z: style palette size (0: no style),
                        // w: flags (kBlendResume | kBlendFinal | kBlendSlabIds | kFrameHalfSh | kFrameDepthKeys)
    uvec4 window;       // pixels x0, y0 (inclusive) to x1, y1 (exclusive) the frame must draw: the
                        // whole image, or a click's pixel (what reaches no pixel in it is culled)
};

// One projected Gaussian, written by preprocess and read by emit_keys and blend.
struct Splat {
    vec2 mean;          // image position; pixel (i, j) has its centre at (i + 0.5, j + 0.5)
    float depth;        // view-space z
    float opacity;      // after the antialiasing compensation
    vec4 conic;         // inverse 2D covariance (a, b, c) and w: the squared Mahalanobis extent
    vec4 color;         // rgb from SH, w: unused
};

// A streamed slab's labels from the scene's (render/gather_labels.comp).
struct GatherPush {
    uvec4 count;        // x: Gaussians in the slab
};

// Which window of every tile's list a dispatch walks (render/tile_window.glsl).
struct TileWindowPush {
    uvec4 window;       // x: window index, y: windows the frame was recorded with, z, w: unused
};

// One pixel of the last frame, picked (render/pick_pixel.comp): where a click lands.
struct PickPush {
    uvec4 pixel;        // x, y, window index, w: 0 first walk, 1 second walk (tau x opacity)
    uvec4 windows;      // x: windows of the pixel's tile, y, z, w: unused
};
PG_CONST uint kPickWalkWords = 13u;  // one walk's state between the pick's windows
struct PixelPick {
    uvec4 ids;          // dominant surface's weighted median Gaussian, tau Gaussian (kNoGaussian: none), unused, unused
    vec4 depths;        // that Gaussian's depth, tau depth, unused, unused
    vec4 weights;       // the surface's summed weight alpha * T, final opacity 1 - T, the tau used, unused
};

#ifdef __cplusplus
static_assert(sizeof(PickPush) == 32);
static_assert(sizeof(TileWindowPush) == 16);
static_assert(sizeof(GatherPush) == 16);
static_assert(sizeof(PixelPick) == 48);
static_assert(sizeof(FrameParams) == 192);
static_assert(sizeof(Splat) == 48);
}  // namespace pg::render::gpu
#endif
#undef PG_CONST
#endif

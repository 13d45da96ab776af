// Layouts and constants shared by engine/segment/picture_passes (C++), seg::ViewMask::overlay
// (the CPU path of exported overlays) and shaders/segment/{overlay,pixel_objects}.comp: one
// definition, no drift.
#ifndef PG_PICTURE_SHARED_H
#define PG_PICTURE_SHARED_H

#ifdef __cplusplus
#include <cstdint>
namespace pg::seg::gpu {
using uint = uint32_t;
#define PG_CONST inline constexpr
#else
#define PG_CONST const
#endif

PG_CONST uint kPictureSide = 16;          // a workgroup covers kPictureSide^2 pixels
PG_CONST float kOverlayRender = 0.45;     // inside an object: this much of the render ...
PG_CONST float kOverlayColour = 0.55;     // ... and this much of the object's colour

struct OverlayPush {
    uint width, height;
    uint palette_size;  // labels at or past it are drawn as unlabelled
    uint has_labels;    // 0: the render alone (the label and palette bindings are not read)
};

struct PixelObjectsPush {
    uint width, height;
    uint pad0, pad1;
};

#ifdef __cplusplus
static_assert(sizeof(OverlayPush) == 16);
static_assert(sizeof(PixelObjectsPush) == 16);
}  // namespace pg::seg::gpu
#endif
#undef PG_CONST
#endif

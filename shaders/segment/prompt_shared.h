// Layouts shared by the prompt encoder (engine/segment/prompt_encoder) and its kernels
// (shaders/segment/click_weights, roi_compact): one definition, no drift. The vec4 members sit at
// 16-byte offsets, so std430 and C++ agree byte for byte.
#ifndef PG_PROMPT_SHARED_H
#define PG_PROMPT_SHARED_H

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
namespace pg::seg::gpu {
using vec4 = glm::vec4;
using uint = uint32_t;
#define PG_PROMPT_CONST inline constexpr
#else
#define PG_PROMPT_CONST const
#endif

PG_PROMPT_CONST uint kPromptGroup = 256;  // one invocation per Gaussian

// segment/click_weights: every Gaussian's positive and negative click weights and ROI flag.
struct ClickWeightsPush {
    uint count;
    uint anchor_count;
    float inv_two_sigma2;
    float half_length;
    float half_width;
    float pad0, pad1, pad2;
    vec4 centre;       // ROI anchor
    vec4 length_axis;  // unit, perpendicular to up
    vec4 width_axis;
};

// segment/roi_compact: the flagged Gaussians' indices and weights, in scene order.
struct RoiCompactPush {
    uint count;
};

#ifdef __cplusplus
static_assert(sizeof(ClickWeightsPush) == 80);
static_assert(sizeof(RoiCompactPush) == 4);
}  // namespace pg::seg::gpu
#endif
#undef PG_PROMPT_CONST
#endif

#version 450
// Gathers the ROI's Gaussian indices and their click weights into dense arrays, at the
// offsets of the prefix sum over the ROI flags (so they stay in index order).
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/prompt_shared.h"

layout(local_size_x = kPromptGroup) in;
layout(std430, binding = 0) readonly buffer Roi { uint roi[]; };
layout(std430, binding = 1) readonly buffer Offsets { uint offsets[]; };
layout(std430, binding = 2) readonly buffer Weights { vec2 weights[]; };
layout(std430, binding = 3) writeonly buffer Indices { uint indices[]; };
layout(std430, binding = 4) writeonly buffer RoiWeights { vec2 roi_weights[]; };
layout(push_constant) uniform Push { RoiCompactPush pc; };

void main() {
    uint i = pg_global_index();
    if (i >= pc.count || roi[i] == 0u) return;
    uint o = offsets[i];
    indices[o] = i;
    roi_weights[o] = weights[i];
}

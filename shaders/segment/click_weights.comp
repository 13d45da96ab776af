#version 450
// The prompt encoder's per-Gaussian pass: w = exp(-|mu - p|^2 / (2 sigma^2)), the maximum over
// positive clicks and over negative clicks in two channels, and whether the Gaussian lies in
// the ROI column (|along length| <= l/2, |along width| <= w/2 around the anchor, any height).
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/prompt_shared.h"

layout(local_size_x = kPromptGroup) in;
layout(std430, binding = 0) readonly buffer Means { vec4 means[]; };      // xyz, opacity logit
layout(std430, binding = 1) readonly buffer Anchors { vec4 anchors[]; };  // xyz, w: +1 positive / -1 negative
layout(std430, binding = 2) writeonly buffer Weights { vec2 weights[]; }; // positive, negative
layout(std430, binding = 3) writeonly buffer Roi { uint roi[]; };         // 1 inside, 0 outside
layout(push_constant) uniform Push { ClickWeightsPush pc; };

void main() {
    uint i = pg_global_index();
    if (i >= pc.count) return;
    vec3 mu = means[i].xyz;
    vec2 w = vec2(0.0);
    for (uint k = 0u; k < pc.anchor_count; ++k) {
        vec3 d = mu - anchors[k].xyz;
        float v = exp(-dot(d, d) * pc.inv_two_sigma2);
        if (anchors[k].w > 0.0) w.x = max(w.x, v); else w.y = max(w.y, v);
    }
    weights[i] = w;
    vec3 rel = mu - pc.centre.xyz;
    roi[i] = (abs(dot(rel, pc.length_axis.xyz)) <= pc.half_length && abs(dot(rel, pc.width_axis.xyz)) <= pc.half_width)
                 ? 1u : 0u;
}

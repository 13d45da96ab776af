#version 450
// Front-to-back blending, one workgroup per 16x16 tile: splats are staged through shared
// memory in batches, and the group stops once every pixel is saturated. The inner loop is
// branch-free: SIMD drivers (lavapipe) run divergent lanes in lockstep anyway.
#extension GL_GOOGLE_include_directive : require
#include "render/render_shared.h"

layout(local_size_x = 16, local_size_y = 16) in;
layout(std430, binding = 0) readonly buffer Frame { FrameParams frame; };
layout(std430, binding = 1) readonly buffer Splats { Splat splats[]; };
layout(std430, binding = 2) readonly buffer Values { uint values[]; };
layout(std430, binding = 3) readonly buffer Ranges { uvec2 ranges[]; };
layout(std430, binding = 4) writeonly buffer Image { vec4 image[]; };   // rgb, alpha
layout(std430, binding = 5) writeonly buffer Aux { uvec4 aux[]; };     // depth, tau-depth, tau-id, contributors

// Structure of arrays: each lane reads the same element, one vec4 at a time.
shared vec4 s_mean_opacity[kBlendGroup];  // mean.xy, opacity, depth
shared vec4 s_conic[kBlendGroup];         // a, b, c, unused
shared vec4 s_color[kBlendGroup];         // rgb, unused
shared uint s_id[kBlendGroup];
shared uint done_count;

void main() {
    uvec2 pix = gl_GlobalInvocationID.xy;
    uint width = frame.size.x, height = frame.size.y;
    bool inside = pix.x < width && pix.y < height;
    uint tile = gl_WorkGroupID.y * frame.size.z + gl_WorkGroupID.x;
    uvec2 range = ranges[tile];
    vec2 center = vec2(pix) + 0.5;
    float tau = frame.background.w;

    if (gl_LocalInvocationIndex == 0u) done_count = 0u;
    barrier();

    bool done = !inside;
    if (done) atomicAdd(done_count, 1u);
    float T = 1.0;
    vec3 C = vec3(0.0);
    float D = 0.0, Wsum = 0.0;
    float tau_depth = 0.0;
    uint tau_id = kNoGaussian, contributors = 0u;

    for (uint start = range.x; start < range.y; start += kBlendGroup) {
        barrier();
        if (done_count == kBlendGroup) break;  // uniform: no thread changes it before the next barrier
        uint k = start + gl_LocalInvocationIndex;
        if (k < range.y) {
            uint id = values[k];
            Splat sp = splats[id];
            s_mean_opacity[gl_LocalInvocationIndex] = vec4(sp.mean, sp.opacity, sp.depth);
            s_conic[gl_LocalInvocationIndex] = sp.conic;
            s_color[gl_LocalInvocationIndex] = sp.color;
            s_id[gl_LocalInvocationIndex] = id;
        }
        barrier();
        if (done) continue;
        uint count = min(kBlendGroup, range.y - start);
        for (uint j = 0u; j < count; ++j) {
            vec4 mo = s_mean_opacity[j];
            vec4 con = s_conic[j];
            vec2 d = mo.xy - center;
            float power = -0.5 * (con.x * d.x * d.x + con.z * d.y * d.y) - con.y * d.x * d.y;
            float alpha = min(kAlphaMax, mo.z * exp(min(power, 0.0)));
            float test_T = T * (1.0 - alpha);
            bool use = power <= 0.0 && alpha >= kAlphaMin;
            // The Gaussian that would push T under the floor is not blended; the pixel is done.
            if (use && test_T < kTransmittanceMin) {
                done = true;
                break;
            }
            float w = use ? alpha * T : 0.0;
            C += s_color[j].rgb * w;
            D += mo.w * w;
            Wsum += w;
            contributors += use ? 1u : 0u;
            T = use ? test_T : T;
            bool hit = use && tau_id == kNoGaussian && 1.0 - T >= tau;
            tau_id = hit ? s_id[j] : tau_id;
            tau_depth = hit ? mo.w : tau_depth;
        }
        if (done) atomicAdd(done_count, 1u);
    }
    if (!inside) return;
    uint p = pix.y * width + pix.x;
    image[p] = vec4(C + T * frame.background.rgb, 1.0 - T);
    aux[p] = uvec4(floatBitsToUint(Wsum > 0.0 ? D / Wsum : 0.0), floatBitsToUint(tau_depth), tau_id, contributors);
}

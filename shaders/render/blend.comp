#version 450
// Front-to-back blending, one workgroup per 16x16 tile: splats are staged through shared
// memory in batches, and the group stops once every pixel is saturated.
#extension GL_GOOGLE_include_directive : require
#include "render/render_shared.h"

layout(local_size_x = 16, local_size_y = 16) in;
layout(std430, binding = 0) readonly buffer Frame { FrameParams frame; };
layout(std430, binding = 1) readonly buffer Splats { Splat splats[]; };
layout(std430, binding = 2) readonly buffer Values { uint values[]; };
layout(std430, binding = 3) readonly buffer Ranges { uvec2 ranges[]; };
layout(std430, binding = 4) writeonly buffer Image { vec4 image[]; };   // rgb, alpha
layout(std430, binding = 5) writeonly buffer Aux { uvec4 aux[]; };     // depth, tau-depth, tau-id, contributors

shared Splat batch[kBlendGroup];
shared uint batch_id[kBlendGroup];
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
            batch_id[gl_LocalInvocationIndex] = id;
            batch[gl_LocalInvocationIndex] = splats[id];
        }
        barrier();
        uint count = min(kBlendGroup, range.y - start);
        for (uint j = 0u; !done && j < count; ++j) {
            vec2 d = batch[j].mean - center;
            vec4 con = batch[j].conic;
            float power = -0.5 * (con.x * d.x * d.x + con.z * d.y * d.y) - con.y * d.x * d.y;
            if (power > 0.0) continue;
            float alpha = min(kAlphaMax, batch[j].opacity * exp(power));
            if (alpha < kAlphaMin) continue;
            float test_T = T * (1.0 - alpha);
            if (test_T < kTransmittanceMin) {
                done = true;
                atomicAdd(done_count, 1u);
                break;
            }
            float w = alpha * T;
            C += batch[j].color.rgb * w;
            D += batch[j].depth * w;
            Wsum += w;
            ++contributors;
            T = test_T;
            if (tau_id == kNoGaussian && 1.0 - T >= tau) {
                tau_id = batch_id[j];
                tau_depth = batch[j].depth;
            }
        }
    }
    if (!inside) return;
    uint p = pix.y * width + pix.x;
    image[p] = vec4(C + T * frame.background.rgb, 1.0 - T);
    aux[p] = uvec4(floatBitsToUint(Wsum > 0.0 ? D / Wsum : 0.0), floatBitsToUint(tau_depth), tau_id, contributors);
}

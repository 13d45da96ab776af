// Front-to-back blending, one workgroup per 16x16 tile: splats are staged through shared
// memory in batches, and the group stops once every pixel is saturated. The inner loop is
// branch-free: SIMD drivers (lavapipe) run divergent lanes in lockstep anyway. The including
// shader sets PG_TILE_WINDOWS (render/tile_window.glsl): 0 walks each tile's whole list, 1 one
// window of it per dispatch.
#include "render/render_shared.h"
#include "render/tile_test.glsl"
#include "render/splat_alpha.glsl"
#include "render/tile_runs.glsl"
#include "render/tile_window.glsl"

layout(local_size_x = 16, local_size_y = 16) in;
layout(std430, binding = 0) readonly buffer Frame { FrameParams frame; };
layout(std430, binding = 1) readonly buffer Splats { Splat splats[]; };
layout(std430, binding = 2) readonly buffer Values { uint values[]; };
layout(std430, binding = 3) readonly buffer Ranges { uvec2 ranges[]; };
layout(std430, binding = 4) writeonly buffer Image { vec4 image[]; };   // rgb, alpha
layout(std430, binding = 5) writeonly buffer Aux { uvec4 aux[]; };     // depth, tau-depth, tau-id, contributors
layout(std430, binding = 6) readonly buffer SlabIds { uint slab_ids[]; };  // scene id of each slab Gaussian
layout(std430, binding = 7) readonly buffer CarryIn { uint carry_in[]; };  // kCarryWords per pixel
layout(std430, binding = 8) writeonly buffer CarryOut { uint carry_out[]; };
// The state between windows of one tile's list (kCarryWords per pixel).
layout(std430, binding = 9) readonly buffer WindowIn { uint window_in[]; };
layout(std430, binding = 10) writeonly buffer WindowOut { uint window_out[]; };
layout(push_constant) uniform Push { TileWindowPush pc; };

// Word i of the carried state: from the last slab (first window) or the last window.
uint carried(bool first, uint i) { return first ? carry_in[i] : window_in[i]; }
void carry(bool last, uint i, uint v) {
    if (last) carry_out[i] = v;
    else window_out[i] = v;
}

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
    const TileWindow tw = tile_window(ranges[tile], pc.window.x, pc.window.y);
    if (tw.skip) return;  // uniform over the group, before any barrier
    const uvec2 range = tw.range;
    vec2 center = vec2(pix) + 0.5;
    float tau = frame.background.w;

    uint flags = frame.capacity.w;
    uint p = pix.y * width + pix.x;

    if (gl_LocalInvocationIndex == 0u) done_count = 0u;
    barrier();

    float T = 1.0;
    vec3 C = vec3(0.0);
    float D = 0.0, Wsum = 0.0;
    float tau_depth = 0.0;
    uint tau_id = kNoGaussian, contributors = 0u;
    bool done = !inside;
    if ((!tw.first || (flags & kBlendResume) != 0u) && inside) {
        uint c = p * kCarryWords;
        C = vec3(uintBitsToFloat(carried(tw.first, c)), uintBitsToFloat(carried(tw.first, c + 1u)),
                 uintBitsToFloat(carried(tw.first, c + 2u)));
        T = uintBitsToFloat(carried(tw.first, c + 3u));
        D = uintBitsToFloat(carried(tw.first, c + 4u));
        Wsum = uintBitsToFloat(carried(tw.first, c + 5u));
        tau_depth = uintBitsToFloat(carried(tw.first, c + 6u));
        tau_id = carried(tw.first, c + 7u);
        contributors = carried(tw.first, c + 8u);
        done = carried(tw.first, c + 9u) != 0u;
    }
    const uint tau_before = tau_id;  // a tau Gaussian of an earlier slab is a scene id already
    if (done) atomicAdd(done_count, 1u);

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
            s_runs[gl_LocalInvocationIndex] = tile_runs_reached(sp, gl_WorkGroupID.xy * kTileSize);
        } else {
            s_runs[gl_LocalInvocationIndex] = 0u;
        }
        barrier();
        uint count = min(kBlendGroup, range.y - start);
        tile_runs_build(count);
        barrier();
        if (done) continue;
        uint run = gl_LocalInvocationIndex >> 3;
        uint run_count = s_run_count[run];
        for (uint t = 0u; t < run_count; ++t) {
            uint j = tile_runs_entry(run, t);
            vec4 mo = s_mean_opacity[j];
            bool use;
            float alpha = splat_alpha(mo.xy, mo.z, s_conic[j].xyz, center, use);
            float test_T = T * (1.0 - alpha);
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
    if ((flags & kBlendSlabIds) != 0u && tau_before == kNoGaussian && tau_id != kNoGaussian) tau_id = slab_ids[tau_id];
    if (!tw.last || (flags & kBlendFinal) == 0u) {
        uint c = p * kCarryWords;
        carry(tw.last, c, floatBitsToUint(C.r));
        carry(tw.last, c + 1u, floatBitsToUint(C.g));
        carry(tw.last, c + 2u, floatBitsToUint(C.b));
        carry(tw.last, c + 3u, floatBitsToUint(T));
        carry(tw.last, c + 4u, floatBitsToUint(D));
        carry(tw.last, c + 5u, floatBitsToUint(Wsum));
        carry(tw.last, c + 6u, floatBitsToUint(tau_depth));
        carry(tw.last, c + 7u, tau_id);
        carry(tw.last, c + 8u, contributors);
        carry(tw.last, c + 9u, done ? 1u : 0u);
        return;
    }
    image[p] = vec4(C + T * frame.background.rgb, 1.0 - T);
    aux[p] = uvec4(floatBitsToUint(Wsum > 0.0 ? D / Wsum : 0.0), floatBitsToUint(tau_depth), tau_id, contributors);
}

// Front-to-back blending, one workgroup per 16x16 tile: splats are staged through shared
// memory in batches, and the group stops once every pixel is saturated. The inner loop is
// branch-free: SIMD drivers (lavapipe) run divergent lanes in lockstep anyway. The including
// shader sets PG_TILE_WINDOWS (render/tile_window.glsl): 0 walks each tile's whole list, 1 one
// window of it per dispatch. lavapipe reads shared memory at an address that varies between
// lanes with a scalar load per lane and component, so the loop reads as few words per splat as
// it can: a run's list one word per four entries, and no Gaussian ids (the tau Gaussian is kept
// as its key's position and looked up once per pixel).
#include "render/render_shared.h"
#ifndef PG_RUN_ROWS
#error "define PG_RUN_ROWS (pixels per invocation, one column: 1, 2 or 4) before including blend.glsl"
#endif
#include "render/tile_test.glsl"
#include "render/splat_alpha.glsl"
#include "render/tile_runs.glsl"
#include "render/tile_window.glsl"

layout(local_size_x = 16, local_size_y = 16 / PG_RUN_ROWS) in;
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
shared uint done_count;

// One pixel's blend so far.
struct PixelState {
    vec3 C;
    float T, D, Wsum, tau_depth;
    uint tau_id, contributors;
    bool done;
};

// Blends one staged splat into the pixel, unless the pixel is done or the splat misses it. The
// splat that would push T under the floor is not blended; the pixel is done.
// `key`: the splat's position in the tile keys; tau_id holds it until the pixel's state is written.
void blend_step(inout PixelState s, vec4 mo, vec3 conic, vec3 color, uint key, vec2 center, float tau) {
    bool use;
    float alpha = splat_alpha(mo.xy, mo.z, conic, center, use);
    use = use && !s.done;
    float test_T = s.T * (1.0 - alpha);
    bool stop = use && test_T < kTransmittanceMin;
    s.done = s.done || stop;
    use = use && !stop;
    float w = use ? alpha * s.T : 0.0;
    s.C += color * w;
    s.D += mo.w * w;
    s.Wsum += w;
    s.contributors += use ? 1u : 0u;
    s.T = use ? test_T : s.T;
    bool hit = use && s.tau_id == kNoGaussian && 1.0 - s.T >= tau;
    s.tau_id = hit ? key : s.tau_id;
    s.tau_depth = hit ? mo.w : s.tau_depth;
}

// A pixel's state at the start of this dispatch: fresh, or carried from the last slab or window.
PixelState pixel_start(bool inside, uint p, TileWindow tw, uint flags) {
    PixelState px = PixelState(vec3(0.0), 1.0, 0.0, 0.0, 0.0, kNoGaussian, 0u, !inside);
    if ((!tw.first || (flags & kBlendResume) != 0u) && inside) {
        uint c = p * kCarryWords;
        px.C = vec3(uintBitsToFloat(carried(tw.first, c)), uintBitsToFloat(carried(tw.first, c + 1u)),
                    uintBitsToFloat(carried(tw.first, c + 2u)));
        px.T = uintBitsToFloat(carried(tw.first, c + 3u));
        px.D = uintBitsToFloat(carried(tw.first, c + 4u));
        px.Wsum = uintBitsToFloat(carried(tw.first, c + 5u));
        px.tau_depth = uintBitsToFloat(carried(tw.first, c + 6u));
        px.tau_id = carried(tw.first, c + 7u);
        px.contributors = carried(tw.first, c + 8u);
        px.done = carried(tw.first, c + 9u) != 0u;
    }
    return px;
}

// Writes a pixel's state: the image, or the carry to the next slab or window. tau_before: its
// tau id at the start (an id already; one found since is a key position).
void pixel_end(PixelState px, uint tau_before, uint p, TileWindow tw, uint flags) {
    if (tau_before == kNoGaussian && px.tau_id != kNoGaussian) {
        px.tau_id = values[px.tau_id];
        if ((flags & kBlendSlabIds) != 0u) px.tau_id = slab_ids[px.tau_id];
    }
    if (!tw.last || (flags & kBlendFinal) == 0u) {
        uint c = p * kCarryWords;
        carry(tw.last, c, floatBitsToUint(px.C.r));
        carry(tw.last, c + 1u, floatBitsToUint(px.C.g));
        carry(tw.last, c + 2u, floatBitsToUint(px.C.b));
        carry(tw.last, c + 3u, floatBitsToUint(px.T));
        carry(tw.last, c + 4u, floatBitsToUint(px.D));
        carry(tw.last, c + 5u, floatBitsToUint(px.Wsum));
        carry(tw.last, c + 6u, floatBitsToUint(px.tau_depth));
        carry(tw.last, c + 7u, px.tau_id);
        carry(tw.last, c + 8u, px.contributors);
        carry(tw.last, c + 9u, px.done ? 1u : 0u);
        return;
    }
    image[p] = vec4(px.C + px.T * frame.background.rgb, 1.0 - px.T);
    aux[p] = uvec4(floatBitsToUint(px.Wsum > 0.0 ? px.D / px.Wsum : 0.0), floatBitsToUint(px.tau_depth), px.tau_id,
                   px.contributors);
}

const uint kInvocations = kBlendGroup / PG_RUN_ROWS;

void main() {
    const uint width = frame.size.x, height = frame.size.y;
    const uint tile = gl_WorkGroupID.y * frame.size.z + gl_WorkGroupID.x;
    const TileWindow tw = tile_window(ranges[tile], pc.window.x, pc.window.y);
    if (tw.skip) return;  // uniform over the group, before any barrier
    const uvec2 range = tw.range;
    const float tau = frame.background.w;
    const uint flags = frame.capacity.w;
    const uint lid = gl_LocalInvocationIndex;

    if (lid == 0u) done_count = 0u;
    barrier();

    // This invocation's pixels: PG_RUN_ROWS rows of one column (render/tile_runs.glsl).
    uvec2 pix[PG_RUN_ROWS];
    vec2 center[PG_RUN_ROWS];
    bool inside[PG_RUN_ROWS];
    PixelState px[PG_RUN_ROWS];
    uint tau_before[PG_RUN_ROWS];
    uint done_here = 0u;
    for (uint r = 0u; r < PG_RUN_ROWS; ++r) {
        pix[r] = tile_runs_pixel(r);
        center[r] = vec2(pix[r]) + 0.5;
        inside[r] = pix[r].x < width && pix[r].y < height;
        px[r] = pixel_start(inside[r], pix[r].y * width + pix[r].x, tw, flags);
        tau_before[r] = px[r].tau_id;
        done_here += px[r].done ? 1u : 0u;
    }
    if (done_here != 0u) atomicAdd(done_count, done_here);

    for (uint start = range.x; start < range.y; start += kBlendGroup) {
        barrier();
        if (done_count == kBlendGroup) break;  // uniform: no thread changes it before the next barrier
        for (uint slot = lid; slot < kBlendGroup; slot += kInvocations) {
            uint k = start + slot;
            if (k < range.y) {
                Splat sp = splats[values[k]];
                s_mean_opacity[slot] = vec4(sp.mean, sp.opacity, sp.depth);
                s_conic[slot] = sp.conic;
                s_color[slot] = sp.color;
                s_runs[slot] = tile_runs_reached(sp, gl_WorkGroupID.xy * kTileSize);
            } else {
                s_runs[slot] = 0u;
            }
        }
        barrier();
        tile_runs_build(min(kBlendGroup, range.y - start));
        barrier();
        bool all_done = true;
        for (uint r = 0u; r < PG_RUN_ROWS; ++r) all_done = all_done && px[r].done;
        const uint before = done_here;
        const uint run = lid >> 3;
        const uint run_count = s_run_count[run];
        for (uint t = 0u; t < run_count && !all_done; t += 4u) {
            const uint word = tile_runs_word(run, t);
            for (uint i = 0u; i < 4u; ++i) {
                if (t + i == run_count) break;
                const uint j = (word >> (8u * i)) & 0xFFu;
                const vec4 mo = s_mean_opacity[j];
                const vec3 conic = s_conic[j].xyz, color = s_color[j].rgb;
                for (uint r = 0u; r < PG_RUN_ROWS; ++r) blend_step(px[r], mo, conic, color, start + j, center[r], tau);
            }
            all_done = true;
            for (uint r = 0u; r < PG_RUN_ROWS; ++r) all_done = all_done && px[r].done;
        }
        done_here = 0u;
        for (uint r = 0u; r < PG_RUN_ROWS; ++r) done_here += px[r].done ? 1u : 0u;
        if (done_here != before) atomicAdd(done_count, done_here - before);
    }
    for (uint r = 0u; r < PG_RUN_ROWS; ++r)
        if (inside[r]) pixel_end(px[r], tau_before[r], pix[r].y * width + pix[r].x, tw, flags);
}

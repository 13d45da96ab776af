// Distance-bounded instance rasterization, Algorithm 1 of the PointGauss paper: a pixel takes
// the label of the first Gaussian, front to back in its tile's list, whose label is > 0 and
// whose projected centre lies within rho^2 <= 4 px^2 of the pixel centre; 0 if there is none.
// As in the paper there is no transmittance cut-off: the whole list is walked, so a labelled
// Gaussian behind an opaque unlabelled one still wins (the Occlusion mode fixes that).
//
// One workgroup per 16x16 tile. The tile's list is staged in batches of 256 (as in
// render/blend.comp); of a batch only the labelled Gaussians whose centre is within 2 px of a
// pixel centre of the tile can decide a pixel, and they are few, since a centre lies in one
// tile. Each of them appends its batch position to the list of every 8x1 pixel run it is
// within 2 px of (shared atomics, so in any order). Every pixel tests its run's list and keeps
// the hit of smallest position, the front-most one: exactly the first hit of Algorithm 1.
// A pixel with a hit is done; the group stops once every pixel is.
// The including shader defines PG_TILE_WINDOWS: 0 walks each tile's whole list in one
// dispatch, 1 one window of it per dispatch (render/tile_window.glsl).
#include "render/render_shared.h"
#include "render/tile_window.glsl"

layout(local_size_x = 16, local_size_y = 16) in;
layout(std430, binding = 0) readonly buffer Frame { FrameParams frame; };
layout(std430, binding = 1) readonly buffer Splats { Splat splats[]; };
layout(std430, binding = 2) readonly buffer Values { uint values[]; };
layout(std430, binding = 3) readonly buffer Ranges { uvec2 ranges[]; };
layout(std430, binding = 4) readonly buffer Labels { uint labels[]; };         // per Gaussian, 0: none
layout(std430, binding = 5) writeonly buffer LabelImage { uint label_image[]; };  // per pixel
// A streamed scene's slabs pass the pixel's label on (frame.capacity.w: kBlendResume / kBlendFinal).
layout(std430, binding = 6) readonly buffer CarryIn { uint carry_in[]; };    // kLabelCarryWords per pixel
layout(std430, binding = 7) writeonly buffer CarryOut { uint carry_out[]; };
// The state between windows of one tile's list (kLabelCarryWords per pixel).
layout(std430, binding = 8) readonly buffer WindowIn { uint window_in[]; };
layout(std430, binding = 9) writeonly buffer WindowOut { uint window_out[]; };
layout(push_constant) uniform Push { TileWindowPush pc; };

const float kRho2Max = 4.0;  // the paper's tau: squared distance, in px^2
const uint kRuns = kBlendGroup / 8u;
const uint kRunWords = kBlendGroup / 4u;  // a run's list: up to 256 byte-sized positions

shared vec2 s_mean[kBlendGroup];  // by position in the batch; valid for the listed ones
shared uint s_label[kBlendGroup];
// Run r's list in batch parity p: byte t is byte (t % 4) of s_run_list[p][r * 64 + t / 4].
// Two copies: one is filled and read while the other is cleared for the next batch.
shared uint s_run_list[2][kRuns * kRunWords];
shared uint s_run_count[2][kRuns];
shared uint done_count;

// Squared distance without contraction, so the run test and the pixel test round alike.
float rho2(vec2 d) {
    precise float r = d.x * d.x + d.y * d.y;
    return r;
}

void main() {
    uvec2 pix = gl_GlobalInvocationID.xy;
    uint width = frame.size.x, height = frame.size.y;
    bool inside = pix.x < width && pix.y < height;
    uint tile = gl_WorkGroupID.y * frame.size.z + gl_WorkGroupID.x;
    const TileWindow tw = tile_window(ranges[tile], pc.window.x, pc.window.y);
    if (tw.skip) return;  // uniform over the group, before any barrier
    const uvec2 range = tw.range;
    vec2 center = vec2(pix) + 0.5;
    uint label_count = uint(labels.length());  // reads past the label buffer give 0
    uvec2 origin = gl_WorkGroupID.xy * kTileSize;
    vec2 box_lo = vec2(origin) + 0.5, box_hi = vec2(origin + kTileSize) - 0.5;
    uint lid = gl_LocalInvocationIndex;

    // Thread lid clears words (lid % 8) * 8 .. + 7 of run lid / 8's list: copy 0 here, copy 1
    // in the first batch, and only if there is a second one (a count of 256 clears it all).
    uint clear_run = lid >> 3, clear_word = (lid & 7u) * 8u;
    if (range.y > range.x)
        for (uint w = 0u; w < 8u; ++w) s_run_list[0][clear_run * kRunWords + clear_word + w] = 0u;
    if (lid < kRuns) {
        s_run_count[0][lid] = 0u;
        s_run_count[1][lid] = range.y - range.x > kBlendGroup ? kBlendGroup : 0u;
    }
    if (lid == 0u) done_count = 0u;
    barrier();

    const uint flags = frame.capacity.w;
    const uint c = (pix.y * width + pix.x) * kLabelCarryWords;
    const bool resume = inside && (!tw.first || (flags & kBlendResume) != 0u);
    uint label = resume ? (tw.first ? carry_in[c] : window_in[c]) : 0u;
    bool done = !inside || label != 0u;  // an earlier slab's hit is in front of this slab's
    if (done) atomicAdd(done_count, 1u);

    uint p = 0u;
    for (uint start = range.x; start < range.y; start += kBlendGroup, p ^= 1u) {
        barrier();
        if (done_count == kBlendGroup) break;  // uniform: no thread changes it before the next barrier
        // The other copy was last read before the barrier above and is next filled after the
        // next one: clear the words it used (its counts are reset after the next barrier).
        uint used = s_run_count[p ^ 1u][clear_run];
        for (uint w = 0u; w < 8u; ++w)
            if ((clear_word + w) * 4u < used) s_run_list[p ^ 1u][clear_run * kRunWords + clear_word + w] = 0u;
        uint k = start + lid;
        if (k < range.y) {
            uint id = values[k];
            uint l = id < label_count ? labels[id] : 0u;
            vec2 m = l != 0u ? splats[id].mean : vec2(-1e9);
            // Near the tile at all? (The nearest pixel centre of the tile is at most as far as
            // any pixel's.) Then the runs: the nearest pixel centre of a run is the mean's x
            // clamped to the run, its distance computed exactly as the pixel test does.
            if (rho2(clamp(m, box_lo, box_hi) - m) <= kRho2Max) {
                s_mean[lid] = m;
                s_label[lid] = l;
                for (uint r = 0u; r < kRuns; ++r) {
                    float y = float(origin.y + (r >> 1)) + 0.5;
                    float x0 = float(origin.x + (r & 1u) * 8u) + 0.5;
                    if (rho2(vec2(clamp(m.x, x0, x0 + 7.0), y) - m) <= kRho2Max) {
                        uint t = atomicAdd(s_run_count[p][r], 1u);
                        atomicOr(s_run_list[p][r * kRunWords + (t >> 2)], lid << ((t & 3u) * 8u));
                    }
                }
            }
        }
        barrier();
        if (lid < kRuns) s_run_count[p ^ 1u][lid] = 0u;
        if (done) continue;
        uint run = lid >> 3;
        uint run_count = s_run_count[p][run];
        uint best = kBlendGroup;
        for (uint t = 0u; t < run_count; ++t) {
            uint j = (s_run_list[p][run * kRunWords + (t >> 2)] >> ((t & 3u) * 8u)) & 0xFFu;
            best = rho2(s_mean[j] - center) <= kRho2Max ? min(best, j) : best;
        }
        if (best < kBlendGroup) {
            label = s_label[best];
            done = true;
            atomicAdd(done_count, 1u);
        }
    }
    if (!inside) return;
    if (!tw.last) window_out[c] = label;
    else if ((flags & kBlendFinal) == 0u) carry_out[c] = label;
    else label_image[pix.y * width + pix.x] = label;
}

// Occlusion-aware label rasterization: a pixel blends its tile's Gaussians front to back
// exactly like render/blend.comp (alpha = min(0.99, o * exp(power)), skipped below 1/255,
// stopped before T would fall under 1e-4) and adds each blending weight w = alpha * T to the
// Gaussian's label, unlabelled Gaussians to label 0. The pixel's label is the label with the
// largest weight (ties: the smaller label), provided its opacity 1 - T is at least 0.5; else
// 0. So an unlabelled surface in front hides a labelled one behind it.
//
// Labels > 0 are tracked in kSlots register slots per pixel (label 0 has its own). When a
// new label meets full slots it replaces the slot of smallest weight (ties: the larger label)
// and starts from its own weight; the evicted label's weight is lost. The slots then hold a
// set, independent of the slot order. Same staging, per-run lists and columns of pixels
// (PG_RUN_ROWS) as render/blend.glsl;
// a pixel also stops as soon as its answer can no longer change.
// The including shader defines PG_TILE_WINDOWS: 0 walks each tile's whole list in one
// dispatch, 1 one window of it per dispatch (render/tile_window.glsl).
#extension GL_EXT_control_flow_attributes : require
#include "render/render_shared.h"
#ifndef PG_RUN_ROWS
#error "define PG_RUN_ROWS (pixels per invocation, one column: 1, 2 or 4) before including label_occlusion.glsl"
#endif
#include "render/tile_window.glsl"
#include "render/tile_test.glsl"
#include "render/tile_runs.glsl"
#include "render/splat_alpha.glsl"

layout(local_size_x = 16, local_size_y = 16 / PG_RUN_ROWS) in;
layout(std430, binding = 0) readonly buffer Frame { FrameParams frame; };
layout(std430, binding = 1) readonly buffer Splats { Splat splats[]; };
layout(std430, binding = 2) readonly buffer Values { uint values[]; };
layout(std430, binding = 3) readonly buffer Ranges { uvec2 ranges[]; };
layout(std430, binding = 4) readonly buffer Labels { uint labels[]; };         // per Gaussian, 0: none
layout(std430, binding = 5) writeonly buffer LabelImage { uint label_image[]; };  // per pixel
// A streamed scene's slabs pass the pixel state on (frame.capacity.w: kBlendResume / kBlendFinal).
layout(std430, binding = 6) readonly buffer CarryIn { uint carry_in[]; };    // kLabelCarryWords per pixel
layout(std430, binding = 7) writeonly buffer CarryOut { uint carry_out[]; };
// The state between windows of one tile's list (kLabelCarryWords per pixel).
layout(std430, binding = 8) readonly buffer WindowIn { uint window_in[]; };
layout(std430, binding = 9) writeonly buffer WindowOut { uint window_out[]; };
layout(push_constant) uniform Push { TileWindowPush pc; };

// Word i of the carried state: from the last slab (first window) or the last window.
uint carried(bool first, uint i) { return first ? carry_in[i] : window_in[i]; }
void carry(bool last, uint i, uint v) {
    if (last) carry_out[i] = v;
    else window_out[i] = v;
}

const uint kSlots = 8u;             // labels > 0 tracked per pixel
const float kMinCoverage = 0.5;     // 1 - T below this: the pixel is background (0)
// Early exit margin: what the remaining Gaussians can add to one label, T, widened for float
// rounding (at most ~2344 more additions of relative error 6e-8 each, as alpha >= 1/255 and
// T >= 1e-4); the result is the same as walking the whole list.
const float kDecideSlack = 1.001;
const float kDecideRounding = 2e-4;

shared vec4 s_mean_opacity[kBlendGroup];  // mean.xy, opacity, unused
shared vec4 s_conic[kBlendGroup];         // a, b, c, unused
shared uint s_label[kBlendGroup];
shared uint done_count;

// One pixel's label weights so far.
struct PixelLabels {
    float T;
    float w0;  // weight of label 0
    uint slot_label[kSlots];
    float slot_w[kSlots];
    bool done;
};

// A pixel's state at the start of this dispatch: fresh, or carried from the last slab or window.
PixelLabels labels_start(bool inside, uint c, TileWindow tw, uint flags) {
    PixelLabels px;
    px.T = 1.0;
    px.w0 = 0.0;
    [[unroll]] for (uint s = 0u; s < kSlots; ++s) {
        px.slot_label[s] = 0u;  // empty slots: label 0, weight 0 (real weights are > 0)
        px.slot_w[s] = 0.0;
    }
    px.done = !inside;
    if ((!tw.first || (flags & kBlendResume) != 0u) && inside) {
        px.T = uintBitsToFloat(carried(tw.first, c));
        px.w0 = uintBitsToFloat(carried(tw.first, c + 1u));
        [[unroll]] for (uint s = 0u; s < kSlots; ++s) {
            px.slot_label[s] = carried(tw.first, c + 2u + s);
            px.slot_w[s] = uintBitsToFloat(carried(tw.first, c + 2u + kSlots + s));
        }
        px.done = carried(tw.first, c + 2u + 2u * kSlots) != 0u;
    }
    return px;
}

// Adds one staged splat of label l to the pixel, unless the pixel is done or the splat misses it.
void label_step(inout PixelLabels px, vec4 mo, vec3 conic, uint l, vec2 center) {
    bool use;
    float alpha = splat_alpha(mo.xy, mo.z, conic, center, use);
    use = use && !px.done;
    float test_T = px.T * (1.0 - alpha);
    bool stop = use && test_T < kTransmittanceMin;  // not blended; the pixel is done
    px.done = px.done || stop;
    use = use && !stop;
    float w = use ? alpha * px.T : 0.0;
    px.T = use ? test_T : px.T;
    // Add w to the label's slot; a label not yet held replaces the weakest slot.
    px.w0 += l == 0u ? w : 0.0;
    bool held = l == 0u || !use;
    [[unroll]] for (uint s = 0u; s < kSlots; ++s) {
        bool same = px.slot_label[s] == l && l != 0u;
        px.slot_w[s] += same ? w : 0.0;
        held = held || same;
    }
    // Victim: the smallest weight, ties the larger label; empty slots (weight 0) first.
    uint victim = 0u, victim_label = px.slot_label[0];
    float victim_w = px.slot_w[0];
    [[unroll]] for (uint s = 1u; s < kSlots; ++s) {
        bool weaker = px.slot_w[s] < victim_w || (px.slot_w[s] == victim_w && px.slot_label[s] > victim_label);
        victim = weaker ? s : victim;
        victim_label = weaker ? px.slot_label[s] : victim_label;
        victim_w = weaker ? px.slot_w[s] : victim_w;
    }
    [[unroll]] for (uint s = 0u; s < kSlots; ++s) {
        bool take = !held && s == victim;
        px.slot_label[s] = take ? l : px.slot_label[s];
        px.slot_w[s] = take ? w : px.slot_w[s];
    }
    // Decided: the rest of the list can add at most T to any label (plus rounding), so once the
    // leader is ahead of the runner-up by more than that it stays the argmax, and 1 - T only
    // grows. The leader cannot be evicted: the victim is the weakest.
    float lead = px.w0, second = 0.0;
    [[unroll]] for (uint s = 0u; s < kSlots; ++s) {
        second = max(second, min(lead, px.slot_w[s]));
        lead = max(lead, px.slot_w[s]);
    }
    px.done = px.done || (1.0 - px.T >= kMinCoverage && lead > second + px.T * kDecideSlack + kDecideRounding);
}

// Writes a pixel's state: its label, or the carry to the next slab or window.
void labels_end(PixelLabels px, uint p, TileWindow tw, uint flags) {
    const uint c = p * kLabelCarryWords;
    if (!tw.last || (flags & kBlendFinal) == 0u) {
        carry(tw.last, c, floatBitsToUint(px.T));
        carry(tw.last, c + 1u, floatBitsToUint(px.w0));
        [[unroll]] for (uint s = 0u; s < kSlots; ++s) {
            carry(tw.last, c + 2u + s, px.slot_label[s]);
            carry(tw.last, c + 2u + kSlots + s, floatBitsToUint(px.slot_w[s]));
        }
        carry(tw.last, c + 2u + 2u * kSlots, px.done ? 1u : 0u);
        return;
    }
    uint best = 0u;
    float best_w = px.w0;
    [[unroll]] for (uint s = 0u; s < kSlots; ++s) {
        bool better = px.slot_w[s] > best_w || (px.slot_w[s] == best_w && px.slot_label[s] < best);
        best = better ? px.slot_label[s] : best;
        best_w = better ? px.slot_w[s] : best_w;
    }
    label_image[p] = 1.0 - px.T >= kMinCoverage ? best : 0u;
}

const uint kInvocations = kBlendGroup / PG_RUN_ROWS;

void main() {
    const uint width = frame.size.x, height = frame.size.y;
    const uint tile = gl_WorkGroupID.y * frame.size.z + gl_WorkGroupID.x;
    const TileWindow tw = tile_window(ranges[tile], pc.window.x, pc.window.y);
    if (tw.skip) return;  // uniform over the group, before any barrier
    const uvec2 range = tw.range;
    const uint label_count = uint(labels.length());  // reads past the label buffer give 0
    const uint flags = frame.capacity.w;
    const uint lid = gl_LocalInvocationIndex;

    if (lid == 0u) done_count = 0u;
    barrier();

    // This invocation's pixels: PG_RUN_ROWS rows of one column (render/tile_runs.glsl).
    uvec2 pix[PG_RUN_ROWS];
    vec2 center[PG_RUN_ROWS];
    bool inside[PG_RUN_ROWS];
    PixelLabels px[PG_RUN_ROWS];
    uint done_here = 0u;
    [[unroll]] for (uint r = 0u; r < PG_RUN_ROWS; ++r) {
        pix[r] = tile_runs_pixel(r);
        center[r] = vec2(pix[r]) + 0.5;
        inside[r] = pix[r].x < width && pix[r].y < height;
        px[r] = labels_start(inside[r], (pix[r].y * width + pix[r].x) * kLabelCarryWords, tw, flags);
        done_here += px[r].done ? 1u : 0u;
    }
    if (done_here != 0u) atomicAdd(done_count, done_here);

    for (uint start = range.x; start < range.y; start += kBlendGroup) {
        barrier();
        if (done_count == kBlendGroup) break;  // uniform: no thread changes it before the next barrier
        for (uint slot = lid; slot < kBlendGroup; slot += kInvocations) {
            uint k = start + slot;
            if (k < range.y) {
                uint id = values[k];
                Splat sp = splats[id];
                s_mean_opacity[slot] = vec4(sp.mean, sp.opacity, 0.0);
                s_conic[slot] = sp.conic;
                s_label[slot] = id < label_count ? labels[id] : 0u;
                s_runs[slot] = tile_runs_reached(sp, gl_WorkGroupID.xy * kTileSize);
            } else {
                s_runs[slot] = 0u;
            }
        }
        barrier();
        tile_runs_build(min(kBlendGroup, range.y - start));
        barrier();
        bool all_done = true;
        [[unroll]] for (uint r = 0u; r < PG_RUN_ROWS; ++r) all_done = all_done && px[r].done;
        const uint before = done_here;
        const uint run = lid >> 3;
        const uint run_count = s_run_count[run];
        for (uint t = 0u; t < run_count && !all_done; t += 4u) {
            const uint word = tile_runs_word(run, t);
            for (uint i = 0u; i < 4u; ++i) {
                if (t + i == run_count) break;
                const uint j = (word >> (8u * i)) & 0xFFu;
                const vec4 mo = s_mean_opacity[j];
                const vec3 conic = s_conic[j].xyz;
                const uint l = s_label[j];
                [[unroll]] for (uint r = 0u; r < PG_RUN_ROWS; ++r) label_step(px[r], mo, conic, l, center[r]);
            }
            all_done = true;
            [[unroll]] for (uint r = 0u; r < PG_RUN_ROWS; ++r) all_done = all_done && px[r].done;
        }
        done_here = 0u;
        [[unroll]] for (uint r = 0u; r < PG_RUN_ROWS; ++r) done_here += px[r].done ? 1u : 0u;
        if (done_here != before) atomicAdd(done_count, done_here - before);
    }
    [[unroll]] for (uint r = 0u; r < PG_RUN_ROWS; ++r)
        if (inside[r]) labels_end(px[r], pix[r].y * width + pix[r].x, tw, flags);
}

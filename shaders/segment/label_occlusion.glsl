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
// set, independent of the slot order. Same staging and per-run lists as render/blend.comp;
// a pixel also stops as soon as its answer can no longer change.
// The including shader defines PG_TILE_WINDOWS: 0 walks each tile's whole list in one
// dispatch, 1 one window of it per dispatch (render/tile_window.glsl).
#extension GL_EXT_control_flow_attributes : require
#include "render/render_shared.h"
#include "render/tile_window.glsl"
#include "render/tile_test.glsl"
#include "render/tile_runs.glsl"
#include "render/splat_alpha.glsl"

layout(local_size_x = 16, local_size_y = 16) in;
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

    if (gl_LocalInvocationIndex == 0u) done_count = 0u;
    barrier();

    bool done = !inside;
    if (done) atomicAdd(done_count, 1u);
    float T = 1.0;
    float w0 = 0.0;  // weight of label 0
    uint slot_label[kSlots];
    float slot_w[kSlots];
    [[unroll]] for (uint s = 0u; s < kSlots; ++s) {
        slot_label[s] = 0u;  // empty slots: label 0, weight 0 (real weights are > 0)
        slot_w[s] = 0.0;
    }
    const uint flags = frame.capacity.w;
    const uint c = (pix.y * width + pix.x) * kLabelCarryWords;
    if ((!tw.first || (flags & kBlendResume) != 0u) && inside) {
        T = uintBitsToFloat(carried(tw.first, c));
        w0 = uintBitsToFloat(carried(tw.first, c + 1u));
        [[unroll]] for (uint s = 0u; s < kSlots; ++s) {
            slot_label[s] = carried(tw.first, c + 2u + s);
            slot_w[s] = uintBitsToFloat(carried(tw.first, c + 2u + kSlots + s));
        }
        if (carried(tw.first, c + 2u + 2u * kSlots) != 0u) {
            done = true;
            atomicAdd(done_count, 1u);
        }
    }

    for (uint start = range.x; start < range.y; start += kBlendGroup) {
        barrier();
        if (done_count == kBlendGroup) break;  // uniform: no thread changes it before the next barrier
        uint k = start + gl_LocalInvocationIndex;
        if (k < range.y) {
            uint id = values[k];
            Splat sp = splats[id];
            s_mean_opacity[gl_LocalInvocationIndex] = vec4(sp.mean, sp.opacity, 0.0);
            s_conic[gl_LocalInvocationIndex] = sp.conic;
            s_label[gl_LocalInvocationIndex] = id < label_count ? labels[id] : 0u;
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
            if (use && test_T < kTransmittanceMin) {
                done = true;
                break;
            }
            float w = use ? alpha * T : 0.0;
            T = use ? test_T : T;
            uint l = s_label[j];
            // Add w to the label's slot; a label not yet held replaces the weakest slot.
            w0 += l == 0u ? w : 0.0;
            bool held = l == 0u || !use;
            [[unroll]] for (uint s = 0u; s < kSlots; ++s) {
                bool same = slot_label[s] == l && l != 0u;
                slot_w[s] += same ? w : 0.0;
                held = held || same;
            }
            // Victim: the smallest weight, ties the larger label; empty slots (weight 0) first.
            uint victim = 0u, victim_label = slot_label[0];
            float victim_w = slot_w[0];
            [[unroll]] for (uint s = 1u; s < kSlots; ++s) {
                bool weaker = slot_w[s] < victim_w || (slot_w[s] == victim_w && slot_label[s] > victim_label);
                victim = weaker ? s : victim;
                victim_label = weaker ? slot_label[s] : victim_label;
                victim_w = weaker ? slot_w[s] : victim_w;
            }
            [[unroll]] for (uint s = 0u; s < kSlots; ++s) {
                bool take = !held && s == victim;
                slot_label[s] = take ? l : slot_label[s];
                slot_w[s] = take ? w : slot_w[s];
            }
            // Decided: the rest of the list can add at most T to any label (plus rounding), so
            // once the leader is ahead of the runner-up by more than that it stays the argmax,
            // and 1 - T only grows. The leader cannot be evicted: the victim is the weakest.
            float lead = w0, second = 0.0;
            [[unroll]] for (uint s = 0u; s < kSlots; ++s) {
                second = max(second, min(lead, slot_w[s]));
                lead = max(lead, slot_w[s]);
            }
            if (1.0 - T >= kMinCoverage && lead > second + T * kDecideSlack + kDecideRounding) {
                done = true;
                break;
            }
        }
        if (done) atomicAdd(done_count, 1u);
    }
    if (!inside) return;
    if (!tw.last || (flags & kBlendFinal) == 0u) {
        carry(tw.last, c, floatBitsToUint(T));
        carry(tw.last, c + 1u, floatBitsToUint(w0));
        [[unroll]] for (uint s = 0u; s < kSlots; ++s) {
            carry(tw.last, c + 2u + s, slot_label[s]);
            carry(tw.last, c + 2u + kSlots + s, floatBitsToUint(slot_w[s]));
        }
        carry(tw.last, c + 2u + 2u * kSlots, done ? 1u : 0u);
        return;
    }
    uint best = 0u;
    float best_w = w0;
    [[unroll]] for (uint s = 0u; s < kSlots; ++s) {
        bool better = slot_w[s] > best_w || (slot_w[s] == best_w && slot_label[s] < best);
        best = better ? slot_label[s] : best;
        best_w = better ? slot_w[s] : best_w;
    }
    label_image[pix.y * width + pix.x] = 1.0 - T >= kMinCoverage ? best : 0u;
}

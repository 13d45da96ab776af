#version 450
// One pixel of the last frame, walked front to back exactly as render/blend.comp blends it.
// It reports the Gaussian at which the accumulated opacity first reaches tau (the paper's
// lift) and the pixel's dominant surface: its contributors split into surfaces wherever two
// depth-consecutive ones are further apart than kSurfaceGap x the sum of their standard
// deviations along the ray (their supports do not meet), and the surface of largest total
// weight alpha * T wins. Its weighted median stands for it: the Gaussian at which the
// surface's running weight reaches half its total. Not its heaviest Gaussian: a thin object
// of small, partly transparent Gaussians can chain in depth into a large opaque one behind it
// (a car's body and the road under it, seen at a grazing angle), and that one Gaussian then
// outweighs each of the object's while the object holds most of the surface's weight.
// Occlusion masks label a pixel by the largest summed weight per object, so the surface rule
// picks what the masks show wherever objects are apart in depth, while tau can be reached on a
// translucent blob in front of the object or on the ground behind its edge.
// Two walks: the first finds the surfaces and the winner; the second, walking the same
// contributors the same way, finds the winner's median and tau (tau x the final opacity where
// the first never reached tau, so a translucent surface still lifts without a second frame).
// One invocation: a click is one pixel. Each dispatch walks one window of the tile's list
// (kTileWindow keys, render_shared.h says why) and keeps the walk in `state` for the next.
#extension GL_GOOGLE_include_directive : require
#include "render/render_shared.h"
#include "render/splat_alpha.glsl"

layout(local_size_x = 1) in;
layout(std430, binding = 0) readonly buffer Frame { FrameParams frame; };
layout(std430, binding = 1) readonly buffer Splats { Splat splats[]; };
layout(std430, binding = 2) readonly buffer Values { uint values[]; };
layout(std430, binding = 3) readonly buffer Ranges { uvec2 ranges[]; };
layout(std430, binding = 4) readonly buffer Shapes { vec4 shapes[]; };  // log-scale xyz, quaternion wxyz
layout(std430, binding = 5) writeonly buffer Out { PixelPick pick; };
layout(std430, binding = 6) buffer State { uint state[]; };  // the two walks, kPickWalkWords each
layout(push_constant) uniform Push { PickPush pc; };

struct Walk {
    float T, tau_depth;
    uint tau_id, contributors;
    float cur_w;               // the surface being walked: its summed weight so far
    uint surface;              // and its ordinal
    float best_w;              // the heaviest surface so far: summed weight and ordinal
    uint best_surface;
    uint median_id;            // second walk: where the target surface's weight reached half its total
    float median_depth;
    float last_depth, last_size;
    bool stopped;  // transmittance would have fallen under the floor
};

void save(uint slot, Walk r) {
    const uint b = slot * kPickWalkWords;
    state[b] = floatBitsToUint(r.T);
    state[b + 1u] = floatBitsToUint(r.tau_depth);
    state[b + 2u] = r.tau_id;
    state[b + 3u] = r.contributors;
    state[b + 4u] = floatBitsToUint(r.cur_w);
    state[b + 5u] = r.surface;
    state[b + 6u] = floatBitsToUint(r.best_w);
    state[b + 7u] = r.best_surface;
    state[b + 8u] = r.median_id;
    state[b + 9u] = floatBitsToUint(r.median_depth);
    state[b + 10u] = floatBitsToUint(r.last_depth);
    state[b + 11u] = floatBitsToUint(r.last_size);
    state[b + 12u] = r.stopped ? 1u : 0u;
}

Walk load(uint slot) {
    const uint b = slot * kPickWalkWords;
    return Walk(uintBitsToFloat(state[b]), uintBitsToFloat(state[b + 1u]), state[b + 2u], state[b + 3u],
                uintBitsToFloat(state[b + 4u]), state[b + 5u], uintBitsToFloat(state[b + 6u]), state[b + 7u],
                state[b + 8u], uintBitsToFloat(state[b + 9u]), uintBitsToFloat(state[b + 10u]),
                uintBitsToFloat(state[b + 11u]), state[b + 12u] != 0u);
}

// The Gaussian's standard deviation along the ray (unit direction `ray`, world), as a depth
// extent (times the ray's cosine to the view axis, `cos_z`): sqrt(sum_k (s_k (r_k . ray))^2).
// Flat Gaussians seen face-on are thin along the ray however wide they are.
float ray_extent(uint id, vec3 ray, float cos_z) {
    vec4 q = shapes[2u * id + 1u];
    q /= length(q);
    float r = q.x, x = q.y, y = q.z, z = q.w;
    vec3 c0 = vec3(1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y + r * z), 2.0 * (x * z - r * y));
    vec3 c1 = vec3(2.0 * (x * y - r * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z + r * x));
    vec3 c2 = vec3(2.0 * (x * z + r * y), 2.0 * (y * z - r * x), 1.0 - 2.0 * (x * x + y * y));
    vec3 s = exp(shapes[2u * id].xyz);
    vec3 along = s * vec3(dot(c0, ray), dot(c1, ray), dot(c2, ray));
    return length(along) * cos_z;
}

void close_surface(inout Walk r) {
    if (r.cur_w > r.best_w) {
        r.best_w = r.cur_w;
        r.best_surface = r.surface;
    }
}

// Walks keys range.x .. range.y - 1 on from where r stands; in surface `target` (kNoGaussian:
// none) it notes the Gaussian at which the running weight reaches `half_w`.
void walk(inout Walk r, uvec2 range, vec2 center, float tau, vec3 ray, float cos_z, uint target, float half_w) {
    for (uint k = range.x; k < range.y && !r.stopped; ++k) {
        uint id = values[k];
        Splat sp = splats[id];
        bool use;
        float alpha = splat_alpha(sp.mean, sp.opacity, sp.conic.xyz, center, use);
        if (!use) continue;
        float test_T = r.T * (1.0 - alpha);
        if (test_T < kTransmittanceMin) {  // blend stops here too
            r.stopped = true;
            break;
        }
        float w = alpha * r.T;
        float size = ray_extent(id, ray, cos_z);
        if (r.contributors > 0u && sp.depth - r.last_depth > kSurfaceGap * (size + r.last_size)) {
            close_surface(r);
            r.cur_w = 0.0;
            ++r.surface;
        }
        r.cur_w += w;
        if (r.surface == target && r.median_id == kNoGaussian && r.cur_w >= half_w) {
            r.median_id = id;
            r.median_depth = sp.depth;
        }
        r.last_depth = sp.depth;
        r.last_size = size;
        r.T = test_T;
        ++r.contributors;
        if (r.tau_id == kNoGaussian && 1.0 - r.T >= tau) {
            r.tau_id = id;
            r.tau_depth = sp.depth;
        }
    }
}

void finish(Walk first, Walk second, float tau) {
    pick.ids = uvec4(second.median_id, second.tau_id, 0u, 0u);
    pick.depths = vec4(second.median_depth, second.tau_depth, 0.0, 0.0);
    pick.weights = vec4(first.best_w, 1.0 - first.T, tau, 0.0);
}

void main() {
    uvec2 pix = pc.pixel.xy;
    uvec2 tile = pix / kTileSize;
    const uvec2 full = ranges[tile.y * frame.size.z + tile.x];
    const uint index = pc.pixel.z, len = full.y - full.x;
    const uvec2 range = full.x + uvec2(min(index * kTileWindow, len), min((index + 1u) * kTileWindow, len));
    const bool last = index + 1u == pc.windows.x;
    vec2 center = vec2(pix) + 0.5;
    float tau = frame.background.w;
    vec3 cam_ray = normalize(vec3((center - frame.intrinsics.zw) / frame.intrinsics.xy, 1.0));
    vec3 ray = transpose(mat3(frame.view)) * cam_ray;  // world; view is a rigid transform
    const Walk fresh = Walk(1.0, 0.0, kNoGaussian, 0u, 0.0, 0u, 0.0, 0u, kNoGaussian, 0.0, 0.0, 0.0, false);
    if (pc.pixel.w == 0u) {
        Walk r = index == 0u ? fresh : load(0u);
        walk(r, range, center, tau, ray, cam_ray.z, kNoGaussian, 0.0);
        if (last) {
            close_surface(r);
            if (r.contributors == 0u) finish(r, r, tau);  // an empty pixel: no second walk
        }
        save(0u, r);
        return;
    }
    // The second walk: the winning surface's median, and tau (x the final opacity where the
    // first walk never reached it).
    const Walk r = load(0u);
    if (r.contributors == 0u) return;
    if (r.tau_id == kNoGaussian) tau *= 1.0 - r.T;
    Walk again = index == 0u ? fresh : load(1u);
    walk(again, range, center, tau, ray, cam_ray.z, r.best_surface, 0.5 * r.best_w);
    save(1u, again);
    if (last) finish(r, again, tau);
}

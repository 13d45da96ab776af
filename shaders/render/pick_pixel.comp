#version 450
// One pixel of the last frame, walked front to back exactly as render/blend.comp blends it.
// It reports the Gaussian at which the accumulated opacity first reaches tau (the paper's
// lift) and the pixel's dominant surface: its contributors split into surfaces wherever two
// depth-consecutive ones are further apart than kSurfaceGap x the sum of their standard
// deviations along the ray (their supports do not meet), and the surface of largest total
// weight alpha * T wins; its
// heaviest Gaussian stands for it. Occlusion masks label a pixel by the largest summed
// weight per object, so the surface rule picks what the masks show wherever objects are
// apart in depth, while tau can be reached on a translucent blob in front of the object or
// on the ground behind its edge. A pixel that never reaches tau takes tau x its final
// opacity (a second walk), so a translucent surface still lifts without a second frame.
// One invocation: a click is one pixel, and its tile's list is short.
#extension GL_GOOGLE_include_directive : require
#include "render/render_shared.h"

layout(local_size_x = 1) in;
layout(std430, binding = 0) readonly buffer Frame { FrameParams frame; };
layout(std430, binding = 1) readonly buffer Splats { Splat splats[]; };
layout(std430, binding = 2) readonly buffer Values { uint values[]; };
layout(std430, binding = 3) readonly buffer Ranges { uvec2 ranges[]; };
layout(std430, binding = 4) readonly buffer Shapes { vec4 shapes[]; };  // log-scale xyz, quaternion wxyz
layout(std430, binding = 5) writeonly buffer Out { PixelPick pick; };
layout(push_constant) uniform Push { PickPush pc; };

struct Walk {
    float T, tau_depth;
    uint tau_id, contributors;
    // The surface being walked and the heaviest so far: summed weight, heaviest Gaussian and
    // its weight and depth.
    float cur_w, cur_peak_w, cur_depth;
    uint cur_id;
    float best_w, best_depth;
    uint best_id;
    float last_depth, last_size;
};

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
        r.best_id = r.cur_id;
        r.best_depth = r.cur_depth;
    }
}

Walk walk(uvec2 range, vec2 center, float tau, vec3 ray, float cos_z) {
    Walk r = Walk(1.0, 0.0, kNoGaussian, 0u, 0.0, 0.0, 0.0, kNoGaussian, 0.0, 0.0, kNoGaussian, 0.0, 0.0);
    for (uint k = range.x; k < range.y; ++k) {
        uint id = values[k];
        Splat sp = splats[id];
        vec2 d = sp.mean - center;
        float power = -0.5 * (sp.conic.x * d.x * d.x + sp.conic.z * d.y * d.y) - sp.conic.y * d.x * d.y;
        float alpha = min(kAlphaMax, sp.opacity * exp(min(power, 0.0)));
        if (power > 0.0 || alpha < kAlphaMin) continue;
        float test_T = r.T * (1.0 - alpha);
        if (test_T < kTransmittanceMin) break;  // blend stops here too
        float w = alpha * r.T;
        float size = ray_extent(id, ray, cos_z);
        if (r.contributors > 0u && sp.depth - r.last_depth > kSurfaceGap * (size + r.last_size)) {
            close_surface(r);
            r.cur_w = 0.0;
            r.cur_peak_w = 0.0;
        }
        r.cur_w += w;
        if (w > r.cur_peak_w) {
            r.cur_peak_w = w;
            r.cur_id = id;
            r.cur_depth = sp.depth;
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
    close_surface(r);
    return r;
}

void main() {
    uvec2 pix = pc.pixel.xy;
    uvec2 tile = pix / kTileSize;
    uvec2 range = ranges[tile.y * frame.size.z + tile.x];
    vec2 center = vec2(pix) + 0.5;
    float tau = frame.background.w;
    vec3 cam_ray = normalize(vec3((center - frame.intrinsics.zw) / frame.intrinsics.xy, 1.0));
    vec3 ray = transpose(mat3(frame.view)) * cam_ray;  // world; view is a rigid transform
    Walk r = walk(range, center, tau, ray, cam_ray.z);
    float opacity = 1.0 - r.T;
    if (r.tau_id == kNoGaussian && opacity > 0.0) {
        tau *= opacity;
        Walk again = walk(range, center, tau, ray, cam_ray.z);
        r.tau_id = again.tau_id;
        r.tau_depth = again.tau_depth;
    }
    pick.ids = uvec4(r.best_id, r.tau_id, 0u, 0u);
    pick.depths = vec4(r.best_depth, r.tau_depth, 0.0, 0.0);
    pick.weights = vec4(r.best_w, opacity, tau, 0.0);
}

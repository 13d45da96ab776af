#version 450
// Projects every Gaussian: EWA 2D covariance, opacity-aware extent, tile rectangle, SH colour,
// and the optional style (a palette entry per label that tints the colour or hides the Gaussian).
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "render/render_shared.h"
#include "render/sh.glsl"
#include "render/tile_test.glsl"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Frame { FrameParams frame; };
layout(std430, binding = 1) readonly buffer Means { vec4 means[]; };     // xyz, opacity logit
layout(std430, binding = 2) readonly buffer Shapes { vec4 shapes[]; };   // [2i]: log-scale, [2i+1]: quat wxyz
layout(std430, binding = 3) readonly buffer Coeffs { float sh[]; };
layout(std430, binding = 4) writeonly buffer Splats { Splat splats[]; };
layout(std430, binding = 5) writeonly buffer Touched { uint touched[]; };
layout(std430, binding = 6) writeonly buffer Rects { uvec2 rects[]; };   // tile rect: min | max, 16 bits each
layout(std430, binding = 7) writeonly buffer DepthKeys { uint depth_keys[]; };  // sorted to order Gaussians
layout(std430, binding = 8) writeonly buffer Order { uint order[]; };
layout(std430, binding = 9) readonly buffer Labels { int labels[]; };      // read only with a style
layout(std430, binding = 10) readonly buffer Palette { vec4 palette[]; };  // rgb, a: tint weight, < 0 hides

// Value j of a Gaussian's SH run starting at word `base`: a float, or half j % 2 of word j / 2.
float sh_value(uint base, bool half_sh, uint j) {
    return half_sh ? unpackHalf2x16(floatBitsToUint(sh[base + (j >> 1)]))[j & 1u] : sh[base + j];
}

void cull(uint i) {
    touched[i] = 0u;
    rects[i] = uvec2(0u);
    depth_keys[i] = 0xFFFFFFFFu;  // after every visible one
}

void main() {
    uint i = pg_global_index();
    if (i >= frame.scene.x) return;
    order[i] = i;

    // A hidden Gaussian leaves exactly like a culled one, so it reaches no output.
    uint palette_size = frame.capacity.z;
    vec4 tint = vec4(0.0);
    if (palette_size != 0u) {
        int label = labels[i];
        tint = palette[label >= 0 && uint(label) < palette_size ? uint(label) : 0u];
        if (tint.a < 0.0) { cull(i); return; }
    }

    vec4 m = means[i];
    vec3 p = (frame.view * vec4(m.xyz, 1.0)).xyz;
    if (p.z <= frame.clip.x) { cull(i); return; }

    vec4 q = shapes[2u * i + 1u];
    q /= length(q);
    float r = q.x, x = q.y, y = q.z, z = q.w;
    mat3 R = mat3(1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y + r * z), 2.0 * (x * z - r * y),
                  2.0 * (x * y - r * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z + r * x),
                  2.0 * (x * z + r * y), 2.0 * (y * z - r * x), 1.0 - 2.0 * (x * x + y * y));
    vec3 s = exp(shapes[2u * i].xyz);
    mat3 M = R * mat3(s.x, 0, 0, 0, s.y, 0, 0, 0, s.z);
    mat3 sigma = M * transpose(M);

    float fx = frame.intrinsics.x, fy = frame.intrinsics.y;
    float limx = kFovClamp * frame.clip.y, limy = kFovClamp * frame.clip.z;
    float tx = clamp(p.x / p.z, -limx, limx) * p.z;
    float ty = clamp(p.y / p.z, -limy, limy) * p.z;
    // J (2x3) as the first two columns of a transposed 3x3, so mat3 algebra applies.
    mat3 J = mat3(fx / p.z, 0.0, 0.0, 0.0, fy / p.z, 0.0, -fx * tx / (p.z * p.z), -fy * ty / (p.z * p.z), 0.0);
    mat3 W = mat3(frame.view);
    mat3 T = J * W;
    mat3 cov = T * sigma * transpose(T);
    float a = cov[0][0], b = cov[0][1], c = cov[1][1];
    float det0 = a * c - b * b;
    a += kLowPass;
    c += kLowPass;
    float det = a * c - b * b;
    if (det <= 0.0) { cull(i); return; }

    float opacity = 1.0 / (1.0 + exp(-m.w));
    if (frame.scene.w != 0u) opacity *= sqrt(max(0.000025, det0 / det));
    if (opacity < kAlphaMin) { cull(i); return; }

    // Support: where opacity * exp(-d^T C d / 2) >= 1/255, i.e. d^T C d <= 2 ln(255 opacity).
    float extent2 = 2.0 * log(255.0 * opacity) * 1.0001 + 1e-4;
    vec2 mean = vec2(fx * p.x / p.z + frame.intrinsics.z, fy * p.y / p.z + frame.intrinsics.w);
    vec2 half_size = sqrt(extent2 * vec2(a, c));
    // Pixels whose centres (k + 0.5) can lie inside, then their tiles.
    vec2 lo = ceil(mean - half_size - 0.5);
    vec2 hi = floor(mean + half_size - 0.5);
    // Only the window's pixels (the whole image, or a click's pixel) count.
    vec2 wlo = vec2(frame.window.xy), whi = vec2(frame.window.zw) - 1.0;
    if (hi.x < wlo.x || hi.y < wlo.y || lo.x > whi.x || lo.y > whi.y || lo.x > hi.x || lo.y > hi.y) {
        cull(i);
        return;
    }
    uvec2 pmin = uvec2(max(lo, wlo));
    uvec2 pmax = uvec2(min(hi, whi));
    uvec2 tmin = pmin / kTileSize, tmax = pmax / kTileSize;

    vec3 dir = normalize(m.xyz - frame.camera_pos.xyz);
    uint base = i * frame.scene.y;
    bool half_sh = (frame.capacity.w & kFrameHalfSh) != 0u;
#define SH_COEFF(k) vec3(sh_value(base, half_sh, 3u * (k)), sh_value(base, half_sh, 3u * (k) + 1u), sh_value(base, half_sh, 3u * (k) + 2u))
    vec3 color;
    PG_EVAL_SH(color, frame.scene.z, dir);
#undef SH_COEFF
    if (palette_size != 0u) color = mix(color, tint.rgb, tint.a);

    float inv = 1.0 / det;
    Splat sp;
    sp.mean = mean;
    sp.depth = p.z;
    sp.opacity = opacity;
    sp.conic = vec4(c * inv, -b * inv, a * inv, extent2);
    sp.color = vec4(color, 0.0);
    splats[i] = sp;
    // Count only the tiles the ellipse reaches: a rotated, elongated Gaussian's bounding
    // rectangle holds many it does not (emit_keys runs the same test).
    uint n = (tmax.x - tmin.x + 1u) * (tmax.y - tmin.y + 1u);
    if (n > 2u) {
        vec3 q = sp.conic.xyz;
        n = 0u;
        for (uint ty = tmin.y; ty <= tmax.y; ++ty)
            for (uint tx = tmin.x; tx <= tmax.x; ++tx)
                n += pg_ellipse_hits_tile(mean, q, extent2, uvec2(tx, ty), frame.size.xy) ? 1u : 0u;
    }
    touched[i] = n;
    // Depths are > near > 0, so their float bits order like the floats.
    depth_keys[i] = floatBitsToUint(p.z);
    rects[i] = uvec2(tmin.x | (tmin.y << 16), tmax.x | (tmax.y << 16));
}

#version 450
// LayerNorm over the c channels of each row, plus an optional residual: y = res + LN(x).
// Two passes in f32 (mean, then the mean squared deviation), eps inside the square root,
// biased variance. The sums run over x - x[row, 0], exact for values near each other, so rows
// far from zero lose no digits to the mean. One invocation per row; rows move 8 channels at a
// time (as u64vec4) when c % 8 == 0.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "common/dispatch.glsl"
#include "nn/elementwise_shared.glsl"
#include "nn/pack8.glsl"
layout(local_size_x = PG_NORM_THREADS) in;
// The 8-wide reads through texel buffers: a load in a loop is a loop over the lanes from a
// storage buffer, one vector gather from a texel buffer (on CPU drivers; the same elsewhere).
#define LOAD8(img, j, lo, hi) lo = imageLoad(img, int(2u * (j))), hi = imageLoad(img, int(2u * (j) + 1u))
layout(binding = 0, rgba32f) readonly uniform imageBuffer x4;
layout(std430, binding = 1) readonly buffer X1 { float x1[]; };
layout(binding = 2, rgba32f) readonly uniform imageBuffer g4;
layout(std430, binding = 3) readonly buffer G1 { float g1[]; };
layout(binding = 4, rgba32f) readonly uniform imageBuffer b4;
layout(std430, binding = 5) readonly buffer B1 { float b1[]; };
layout(binding = 6, rgba32f) readonly uniform imageBuffer r4;
layout(std430, binding = 7) readonly buffer R1 { float r1[]; };
layout(std430, binding = 8) writeonly buffer Y8 { u64vec4 y8[]; };
layout(std430, binding = 9) writeonly buffer Y1 { float y1[]; };
layout(push_constant) uniform PushBlock { LayerNormPush pc; };

void main() {
    const uint r = pg_global_index();
    if (r >= pc.rows) return;
    // Wide part [0, 8*n8) and scalar part [8*n8, c): one of them is empty.
    const uint n8 = pc.wide != 0u ? pc.c / 8u : 0u;
    const uint base8 = r * n8, base1 = r * pc.c;
    const bool residual = pc.residual != 0u;

    const float shift = x1[base1];
    vec4 s4 = vec4(0.0);
    float s1 = 0.0;
    for (uint i = 0u; i < n8; ++i) {
        vec4 lo, hi;
        LOAD8(x4, base8 + i, lo, hi);
        s4 += (lo - shift) + (hi - shift);
    }
    for (uint i = 8u * n8; i < pc.c; ++i) s1 += x1[base1 + i] - shift;
    const float mean = ((s4.x + s4.y) + (s4.z + s4.w) + s1) / float(pc.c);  // of x - shift

    vec4 q4 = vec4(0.0);
    float q1 = 0.0;
    for (uint i = 0u; i < n8; ++i) {
        vec4 lo, hi;
        LOAD8(x4, base8 + i, lo, hi);
        lo = (lo - shift) - mean;
        hi = (hi - shift) - mean;
        q4 += lo * lo + hi * hi;
    }
    for (uint i = 8u * n8; i < pc.c; ++i) {
        const float d = (x1[base1 + i] - shift) - mean;
        q1 += d * d;
    }
    const float var = ((q4.x + q4.y) + (q4.z + q4.w) + q1) / float(pc.c);
    const float inv = 1.0 / sqrt(var + pc.eps);

    for (uint i = 0u; i < n8; ++i) {
        vec4 lo, hi, glo, ghi, blo, bhi;
        LOAD8(x4, base8 + i, lo, hi);
        LOAD8(g4, i, glo, ghi);
        LOAD8(b4, i, blo, bhi);
        lo = ((lo - shift) - mean) * inv * glo + blo;
        hi = ((hi - shift) - mean) * inv * ghi + bhi;
        if (residual) {
            vec4 rlo, rhi;
            LOAD8(r4, base8 + i, rlo, rhi);
            lo += rlo;
            hi += rhi;
        }
        y8[base8 + i] = pack8(lo, hi);
    }
    for (uint i = 8u * n8; i < pc.c; ++i) {
        float v = ((x1[base1 + i] - shift) - mean) * inv * g1[i] + b1[i];
        if (residual) v += r1[base1 + i];
        y1[base1 + i] = v;
    }
}

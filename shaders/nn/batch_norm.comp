#version 450
// Inference BatchNorm1d: y = (x - mean) / sqrt(var + eps) * gamma + beta per channel, then
// GELU when asked. An invocation owns 8 channels (moved as u64vec4; 1 channel when c % 8 != 0)
// of a block of rows, so the statistics are read once per block.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "common/dispatch.glsl"
#include "nn/elementwise_shared.glsl"
#include "nn/erf.glsl"
#include "nn/pack8.glsl"
layout(local_size_x = PG_NORM_THREADS) in;
layout(std430, binding = 0) readonly buffer X8 { u64vec4 x8[]; };
layout(std430, binding = 1) readonly buffer X1 { float x1[]; };
layout(std430, binding = 2) readonly buffer Mean8 { u64vec4 mean8[]; };
layout(std430, binding = 3) readonly buffer Mean1 { float mean1[]; };
layout(std430, binding = 4) readonly buffer Var8 { u64vec4 var8[]; };
layout(std430, binding = 5) readonly buffer Var1 { float var1[]; };
layout(std430, binding = 6) readonly buffer Gamma8 { u64vec4 gamma8[]; };
layout(std430, binding = 7) readonly buffer Gamma1 { float gamma1[]; };
layout(std430, binding = 8) readonly buffer Beta8 { u64vec4 beta8[]; };
layout(std430, binding = 9) readonly buffer Beta1 { float beta1[]; };
layout(std430, binding = 10) writeonly buffer Y8 { u64vec4 y8[]; };
layout(std430, binding = 11) writeonly buffer Y1 { float y1[]; };
layout(push_constant) uniform PushBlock { BatchNormPush pc; };

const uint kRowsPerInvocation = PG_BATCH_NORM_ROWS;

vec4 gelu4(vec4 v) { return vec4(pg_gelu(v.x), pg_gelu(v.y), pg_gelu(v.z), pg_gelu(v.w)); }

void main() {
    const uint i = pg_global_index();
    const uint groups = pc.wide != 0u ? pc.c / 8u : pc.c;  // channel groups per row
    const uint blocks = (pc.rows + kRowsPerInvocation - 1u) / kRowsPerInvocation;
    if (i >= groups * blocks) return;
    const uint g = i % groups, r0 = (i / groups) * kRowsPerInvocation;
    const uint r1 = min(r0 + kRowsPerInvocation, pc.rows);
    if (pc.wide != 0u) {
        vec4 mlo, mhi, vlo, vhi, glo, ghi, blo, bhi;
        unpack8(mean8[g], mlo, mhi);
        unpack8(var8[g], vlo, vhi);
        unpack8(gamma8[g], glo, ghi);
        unpack8(beta8[g], blo, bhi);
        const vec4 slo = glo / sqrt(vlo + pc.eps), shi = ghi / sqrt(vhi + pc.eps);
        for (uint r = r0; r < r1; ++r) {
            vec4 lo, hi;
            unpack8(x8[r * groups + g], lo, hi);
            lo = (lo - mlo) * slo + blo;
            hi = (hi - mhi) * shi + bhi;
            if (pc.gelu != 0u) {
                lo = gelu4(lo);
                hi = gelu4(hi);
            }
            y8[r * groups + g] = pack8(lo, hi);
        }
    } else {
        const float scale = gamma1[g] / sqrt(var1[g] + pc.eps);
        const float mean = mean1[g], beta = beta1[g];
        for (uint r = r0; r < r1; ++r) {
            float v = (x1[r * pc.c + g] - mean) * scale + beta;
            if (pc.gelu != 0u) v = pg_gelu(v);
            y1[r * pc.c + g] = v;
        }
    }
}

#version 450
// y = GELU(x) (or erf(x) with erf_only) elementwise (erf.glsl). 8 values per invocation, moved
// as a u64vec4, when n % 8 == 0: lavapipe pays per load instruction per lane, not per byte.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "common/dispatch.glsl"
#include "nn/elementwise_shared.glsl"
#include "nn/erf.glsl"
layout(local_size_x = PG_ELEMENTWISE_THREADS) in;
layout(std430, binding = 0) readonly buffer X8 { u64vec4 x8[]; };
layout(std430, binding = 1) readonly buffer X1 { float x1[]; };
layout(std430, binding = 2) writeonly buffer Y8 { u64vec4 y8[]; };
layout(std430, binding = 3) writeonly buffer Y1 { float y1[]; };
layout(push_constant) uniform PushBlock { GeluPush pc; };

float f(float x) { return pc.erf_only != 0u ? pg_erf(x) : pg_gelu(x); }

uint64_t f2(uint64_t v) {
    const uvec2 p = unpack32(v);
    return pack64(uvec2(floatBitsToUint(f(uintBitsToFloat(p.x))), floatBitsToUint(f(uintBitsToFloat(p.y)))));
}

void main() {
    const uint i = pg_global_index();
    if (pc.wide != 0u) {
        if (i >= pc.n / 8u) return;
        const u64vec4 v = x8[i];
        y8[i] = u64vec4(f2(v.x), f2(v.y), f2(v.z), f2(v.w));
    } else if (i < pc.n) {
        y1[i] = f(x1[i]);
    }
}

#version 450
// y[r, :] = a[r, :] + x[idx[r], :] (f32 rows of c values; 8 per invocation, moved as a
// u64vec4, when c % 8 == 0).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "common/dispatch.glsl"
#include "nn/elementwise_shared.glsl"
layout(local_size_x = PG_ELEMENTWISE_THREADS) in;
layout(std430, binding = 0) readonly buffer A8 { u64vec4 a8[]; };
layout(std430, binding = 1) readonly buffer A1 { float a1[]; };
layout(std430, binding = 2) readonly buffer X8 { u64vec4 x8[]; };
layout(std430, binding = 3) readonly buffer X1 { float x1[]; };
layout(std430, binding = 4) readonly buffer Idx { int idx[]; };
layout(std430, binding = 5) writeonly buffer Y8 { u64vec4 y8[]; };
layout(std430, binding = 6) writeonly buffer Y1 { float y1[]; };
layout(push_constant) uniform PushBlock { AddGatheredPush pc; };

uint64_t add2(uint64_t a, uint64_t b) {
    const vec2 s = uintBitsToFloat(unpack32(a)) + uintBitsToFloat(unpack32(b));
    return pack64(floatBitsToUint(s));
}

void main() {
    const uint i = pg_global_index();
    const uint per_row = pc.wide != 0u ? pc.c / 8u : pc.c;
    if (i >= pc.rows * per_row) return;
    const uint r = i / per_row, k = i % per_row;
    const uint src = uint(idx[r]) * per_row + k;
    if (pc.wide != 0u) {
        const u64vec4 a = a8[i], x = x8[src];
        y8[i] = u64vec4(add2(a.x, x.x), add2(a.y, x.y), add2(a.z, x.z), add2(a.w, x.w));
    } else {
        y1[i] = a1[i] + x1[src];
    }
}

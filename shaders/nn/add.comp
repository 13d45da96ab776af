#version 450
// y = a + b elementwise; 8 values per invocation, moved as a u64vec4, when n % 8 == 0.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "common/dispatch.glsl"
#include "nn/elementwise_shared.glsl"
layout(local_size_x = PG_ELEMENTWISE_THREADS) in;
layout(std430, binding = 0) readonly buffer A8 { u64vec4 a8[]; };
layout(std430, binding = 1) readonly buffer A1 { float a1[]; };
layout(std430, binding = 2) readonly buffer B8 { u64vec4 b8[]; };
layout(std430, binding = 3) readonly buffer B1 { float b1[]; };
layout(std430, binding = 4) writeonly buffer Y8 { u64vec4 y8[]; };
layout(std430, binding = 5) writeonly buffer Y1 { float y1[]; };
layout(push_constant) uniform PushBlock { AddPush pc; };

uint64_t add2(uint64_t a, uint64_t b) {
    const vec2 s = uintBitsToFloat(unpack32(a)) + uintBitsToFloat(unpack32(b));
    return pack64(floatBitsToUint(s));
}

void main() {
    const uint i = pg_global_index();
    if (pc.wide != 0u) {
        if (i >= pc.n / 8u) return;
        const u64vec4 a = a8[i], b = b8[i];
        y8[i] = u64vec4(add2(a.x, b.x), add2(a.y, b.y), add2(a.z, b.z), add2(a.w, b.w));
    } else if (i < pc.n) {
        y1[i] = a1[i] + b1[i];
    }
}

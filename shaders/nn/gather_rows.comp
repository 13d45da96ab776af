#version 450
// y[r, :] = x[idx[r], :] on rows of `words` 32-bit words (any dtype); 8 words per invocation,
// moved as a u64vec4, when words % 8 == 0.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "common/dispatch.glsl"
#include "nn/elementwise_shared.glsl"
layout(local_size_x = PG_ELEMENTWISE_THREADS) in;
layout(std430, binding = 0) readonly buffer X8 { u64vec4 x8[]; };
layout(std430, binding = 1) readonly buffer X1 { uint x1[]; };
layout(std430, binding = 2) readonly buffer Idx { int idx[]; };
layout(std430, binding = 3) writeonly buffer Y8 { u64vec4 y8[]; };
layout(std430, binding = 4) writeonly buffer Y1 { uint y1[]; };
layout(push_constant) uniform PushBlock { GatherRowsPush pc; };

void main() {
    const uint i = pg_global_index();
    const uint per_row = pc.wide != 0u ? pc.words / 8u : pc.words;
    if (i >= pc.rows * per_row) return;
    const uint r = i / per_row, c = i % per_row;
    const uint src = uint(idx[r]) * per_row + c;
    if (pc.wide != 0u) y8[i] = x8[src];
    else y1[i] = x1[src];
}

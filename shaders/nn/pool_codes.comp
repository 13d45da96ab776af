#version 450
// Next level's codes: code[head[m]] >> shift.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/index_shared.glsl"
#include "nn/index_key.glsl"
layout(local_size_x = PG_INDEX_THREADS) in;
layout(std430, binding = 0) readonly buffer Codes { uvec2 codes[]; };
layout(std430, binding = 1) readonly buffer Head { int head_[]; };
layout(std430, binding = 2) writeonly buffer Out { uvec2 out_codes[]; };
layout(push_constant) uniform PushBlock { ShiftPush pc; };

void main() {
    uint m = pg_global_index();
    if (m >= pc.n) return;
    out_codes[m] = key_shr(codes[head_[m]], pc.shift);
}

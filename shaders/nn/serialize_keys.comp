#version 450
// Sort input: keys = code >> shift, values = point index (a stable sort then ranks ties by index).
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/index_shared.glsl"
#include "nn/index_key.glsl"
layout(local_size_x = PG_INDEX_THREADS) in;
layout(std430, binding = 0) readonly buffer Codes { uvec2 codes[]; };
layout(std430, binding = 1) writeonly buffer Keys { uvec2 keys[]; };
layout(std430, binding = 2) writeonly buffer Values { uint values[]; };
layout(push_constant) uniform PushBlock { ShiftPush pc; };

void main() {
    uint i = pg_global_index();
    if (i >= pc.n) return;
    keys[i] = key_shr(codes[i], pc.shift);
    values[i] = i;
}

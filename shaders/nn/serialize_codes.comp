#version 450
// Serialization codes: (batch << 3 depth) | curve(grid), one point per invocation.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/index_shared.glsl"
#include "nn/index_key.glsl"
#include "nn/serialize_curves.glsl"
layout(local_size_x = PG_INDEX_THREADS) in;
layout(std430, binding = 0) readonly buffer Grid { int grid[]; };
layout(std430, binding = 1) readonly buffer Batch { int batch[]; };
layout(std430, binding = 2) writeonly buffer Codes { uvec2 codes[]; };
layout(push_constant) uniform PushBlock { SerializePush pc; };

void main() {
    uint i = pg_global_index();
    if (i >= pc.n) return;
    uvec3 p = uvec3(grid[3u * i], grid[3u * i + 1u], grid[3u * i + 2u]);
    if (pc.swap_xy != 0u) p.xy = p.yx;
    uvec2 code = pc.hilbert != 0u ? hilbert(p, pc.depth) : z_order(p, pc.depth);
    codes[i] = code | key_shl(uint(batch[i]), 3u * pc.depth);
}

#version 450
// Packed (batch, x, y, z) keys with just the bits the maxima need, and point indices as values.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/index_shared.glsl"
#include "nn/index_key.glsl"
layout(local_size_x = PG_INDEX_THREADS) in;
layout(std430, binding = 0) readonly buffer Grid { int grid[]; };
layout(std430, binding = 1) readonly buffer Batch { int batch[]; };
layout(std430, binding = 2) buffer Info { uint info[]; };
layout(std430, binding = 3) writeonly buffer Keys { uvec2 keys[]; };
layout(std430, binding = 4) writeonly buffer Values { uint values[]; };
layout(push_constant) uniform PushBlock { KeyPush pc; };

void main() {
    uint i = pg_global_index();
    if (i >= pc.n) return;
    uvec4 maxima = uvec4(info[PG_INFO_MAX_X], info[PG_INFO_MAX_Y], info[PG_INFO_MAX_Z], info[PG_INFO_MAX_BATCH]);
    uvec4 w = grid_widths(maxima);
    if (i == 0u && w.x + w.y + w.z + w.w > pc.key_bits) atomicOr(info[PG_INFO_FLAGS], PG_FLAG_OVERFLOW);
    uvec3 p = uvec3(grid[3u * i], grid[3u * i + 1u], grid[3u * i + 2u]);
    keys[i] = grid_key(w, p, uint(batch[i]));
    values[i] = i;
}

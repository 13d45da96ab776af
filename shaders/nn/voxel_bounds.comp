#version 450
// Per-axis maxima of grid and batch (and a flag for negative entries) into the info buffer,
// which starts zeroed: a shared-memory max per group, then one atomic per group and word.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/index_shared.glsl"
layout(local_size_x = PG_INDEX_THREADS) in;
layout(std430, binding = 0) readonly buffer Grid { int grid[]; };
layout(std430, binding = 1) readonly buffer Batch { int batch[]; };
layout(std430, binding = 2) buffer Info { uint info[]; };
layout(push_constant) uniform PushBlock { CountPush pc; };

shared uvec4 group_max[PG_INDEX_THREADS];
shared uint group_flags;

void main() {
    uint i = pg_global_index(), l = gl_LocalInvocationIndex;
    if (l == 0u) group_flags = 0u;
    barrier();
    uvec4 m = uvec4(0u);
    if (i < pc.n) {
        ivec4 v = ivec4(grid[3u * i], grid[3u * i + 1u], grid[3u * i + 2u], batch[i]);
        if (any(lessThan(v, ivec4(0)))) atomicOr(group_flags, PG_FLAG_NEGATIVE);
        m = uvec4(max(v, ivec4(0)));
    }
    group_max[l] = m;
    barrier();
    for (uint s = PG_INDEX_THREADS / 2u; s > 0u; s >>= 1u) {
        if (l < s) group_max[l] = max(group_max[l], group_max[l + s]);
        barrier();
    }
    if (l == 0u) {
        uvec4 g = group_max[0];
        atomicMax(info[PG_INFO_MAX_X], g.x);
        atomicMax(info[PG_INFO_MAX_Y], g.y);
        atomicMax(info[PG_INFO_MAX_Z], g.z);
        atomicMax(info[PG_INFO_MAX_BATCH], g.w);
        if (group_flags != 0u) atomicOr(info[PG_INFO_FLAGS], group_flags);
    }
}

#version 450
// Indirect dispatch arguments of the per-tap GEMMs from the rulebook's pair counts: taps
// without pairs cost no workgroups, and the host never waits for the counts.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/conv_shared.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer CountBuf { uint counts[]; };
layout(std430, binding = 1) writeonly buffer ArgBuf { uint args[]; };
layout(push_constant) uniform PushBlock { ConvArgsPush pc; };

void main() {
    const uint t = pg_global_index();
    if (t >= pc.taps) return;
    PG_WRITE_DISPATCH(args, 3u * t, (counts[t] + pc.rows_per_group - 1u) / pc.rows_per_group * pc.col_tiles, pc.limit);
}

#version 450
// Indirect dispatch arguments of one all-taps lanes GEMM (conv_shared.glsl, ConvTapsArgsPush):
// its taps' row groups from the rulebook's schedule, so the host never waits for the counts.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/conv_shared.glsl"
layout(local_size_x = 1) in;
layout(std430, binding = 0) readonly buffer ScheduleBuf { uint schedule[]; };
layout(std430, binding = 1) writeonly buffer ArgBuf { uint args[]; };
layout(push_constant) uniform PushBlock { ConvTapsArgsPush pc; };

void main() {
    const uint groups = schedule[pc.taps];
    PG_WRITE_DISPATCH(args, 0u, groups * pc.col_tiles, pc.limit);
}

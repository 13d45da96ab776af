#version 450
// The rulebook's schedule for the all-taps lanes kernels (conv_shared.glsl, ConvSchedulePush):
// a dispatch then holds exactly the row groups its taps' pairs fill. One invocation: a few
// hundred entries per convolution level, written once per rulebook.
#extension GL_GOOGLE_include_directive : require
#include "nn/conv_shared.glsl"
layout(local_size_x = 1) in;
layout(std430, binding = 0) readonly buffer CountBuf { uint counts[]; };
layout(std430, binding = 1) writeonly buffer ScheduleBuf { uint schedule[]; };
layout(push_constant) uniform PushBlock { ConvSchedulePush pc; };

void main() {
    uint total = 0u;
    for (uint t = 0u; t < pc.taps; ++t) {
        schedule[t] = total;
        const uint groups = (counts[t] + pc.rows_per_group - 1u) / pc.rows_per_group;
        for (uint r = 0u; r < groups; ++r) schedule[pc.taps + 1u + total + r] = t;
        total += groups;
    }
    schedule[pc.taps] = total;
}

#version 450
// Turns a GPU-written item count into indirect dispatch arguments, so a frame never waits
// for the host to read a count back.
#extension GL_GOOGLE_include_directive : require
#include "common/common_shared.h"
#include "common/dispatch.glsl"
layout(local_size_x = 1) in;
layout(std430, binding = 0) readonly buffer Counts { uint counts[]; };
layout(std430, binding = 1) writeonly buffer Args { uint args[]; };
layout(push_constant) uniform Push { IndirectArgsPush pc; };
void main() {
    uint n = counts[pc.count_index];
    if (pc.clamp_count != 0u) n = min(n, pc.clamp_count);
    uint groups = (n + pc.items_per_group - 1u) / pc.items_per_group;
    PG_WRITE_DISPATCH(args, pc.args_index, groups, pc.limit);
}

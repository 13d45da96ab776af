#version 450
// After the points are sorted by label: where each cluster's run of members starts and ends
// (`start` and `end` are zero-filled first, so an empty cluster has an empty run).
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Keys { uint keys[]; };  // labels, sorted
layout(std430, binding = 1) buffer Start { uint start[]; };
layout(std430, binding = 2) buffer End { uint end_[]; };
layout(push_constant) uniform Push { uint n; } pc;

void main() {
    uint i = pg_global_index();
    if (i >= pc.n) return;
    uint key = keys[i];
    if (i == 0u || keys[i - 1u] != key) start[key] = i;
    if (i + 1u == pc.n || keys[i + 1u] != key) end_[key] = i + 1u;
}

#version 450
// After a window's labels are sorted (with their point indices): where each cluster's run of
// members starts and ends. `start` and `end` are zero-filled first, so an empty cluster has an
// empty run.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "compress/kmeans_shared.h"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Keys { uint keys[]; };  // labels, sorted
layout(std430, binding = 1) writeonly buffer Start { uint start[]; };
layout(std430, binding = 2) writeonly buffer End { uint end_[]; };
layout(push_constant) uniform Push { KmeansBoundsPush pc; };

void main() {
    const uint i = pg_global_index();
    if (i >= pc.n) return;
    const uint key = keys[i];
    if (i == 0u || keys[i - 1u] != key) start[key] = i;
    if (i + 1u == pc.n || keys[i + 1u] != key) end_[key] = i + 1u;
}

#version 450
// Conjugate gradient direction: p = z + beta p.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Scalars { WalkScalars scalars[]; };
layout(std430, binding = 1) readonly buffer Z { vec4 z[]; };
layout(std430, binding = 2) buffer P { vec4 p[]; };
layout(push_constant) uniform Push { WalkPush pc; };
#include "segment/walk_common.glsl"

void main() {
    uint vecs = WALK_VECS;
    uint i = pg_global_index();
    if (i >= pc.size.x) return;
    for (uint c = 0u; c < vecs; ++c) {
        vec4 beta = vec4(scalars[4u * c].value.z, scalars[4u * c + 1u].value.z, scalars[4u * c + 2u].value.z,
                         scalars[4u * c + 3u].value.z);
        uint at = i * vecs + c;
        p[at] = z[at] + beta * p[at];
    }
}

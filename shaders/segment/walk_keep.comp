#version 450
// Keeps the label columns named by mode.z's bits (bit l: column l of this solve) of x in best:
// a multigrid solve that stalls or blows up on one column answers with that column's best
// iterate, while the others go on converging.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer X { vec4 x[]; };
layout(std430, binding = 1) buffer Best { vec4 best[]; };
layout(push_constant) uniform Push { WalkPush pc; };
#include "segment/walk_common.glsl"

void main() {
    uint vecs = WALK_VECS;
    uint i = pg_global_index();
    if (i >= pc.size.x) return;
    for (uint c = 0u; c < vecs; ++c) {
        uint at = i * vecs + c;
        vec4 keep = vec4(bvec4((pc.mode.z >> (4u * c)) & 1u, (pc.mode.z >> (4u * c + 1u)) & 1u,
                               (pc.mode.z >> (4u * c + 2u)) & 1u, (pc.mode.z >> (4u * c + 3u)) & 1u));
        best[at] = mix(best[at], x[at], keep);
    }
}

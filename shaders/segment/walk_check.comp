#version 450
// The stop test's measure for a multigrid solve: partial dots r . r / diag (times what the caller's
// weights add: 0 for nodes out of the solve), the quantity the
// Jacobi solve's r . z already is (r . Br of a V-cycle grows with the operator's conditioning,
// so it would ask far more of an ill-posed scene than of an easy one at the same tolerance).
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer R { vec4 r[]; };
layout(std430, binding = 1) readonly buffer Scale { float inv_diag[]; };  // 1 / diag, or a multiple of it
layout(std430, binding = 2) writeonly buffer Partials { vec4 partials[]; };
layout(push_constant) uniform Push { WalkPush pc; };
#include "segment/walk_common.glsl"

void main() {
    uint vecs = WALK_VECS;
    uint i = pg_global_index();
    vec4 dots[kWalkVecs];
    for (uint c = 0u; c < kWalkVecs; ++c) dots[c] = vec4(0.0);
    if (i < pc.size.x) {
        float m = inv_diag[i];
        for (uint c = 0u; c < vecs; ++c) dots[c] = m * r[i * vecs + c] * r[i * vecs + c];
    }
    WALK_STORE_PARTIALS(dots, partials);
}

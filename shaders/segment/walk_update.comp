#version 450
// Conjugate gradient step: x += alpha p, r -= alpha Ap, z = r / diag, partial dots r . z; first
// the columns named by mode.z's bits (bit l: column l of this solve) keep x in best, as it was
// before the step (a multigrid solve that stalls or blows up on one column answers with that
// column's best iterate, while the others go on converging). With the multigrid smoother
// (omega / diag) for 1 / diag, r . z is the stop test's measure r . r / diag times omega.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Scalars { WalkScalars scalars[]; };
// Reads through texel buffers: gathered in vector code on CPU drivers (walk_apply.comp).
layout(binding = 1, rgba32f) readonly uniform imageBuffer p;
layout(binding = 2, rgba32f) readonly uniform imageBuffer ap;
layout(binding = 3, r32f) readonly uniform imageBuffer inv_diag;
layout(std430, binding = 4) buffer X { vec4 x[]; };
layout(std430, binding = 5) buffer R { vec4 r[]; };
layout(std430, binding = 6) writeonly buffer Z { vec4 z[]; };
layout(std430, binding = 7) writeonly buffer Partials { vec4 partials[]; };
layout(std430, binding = 8) buffer Best { vec4 best[]; };
layout(push_constant) uniform Push { WalkPush pc; };
#include "segment/walk_common.glsl"

void main() {
    uint vecs = WALK_VECS;
    uint i = pg_global_index();
    vec4 dots[kWalkVecs];
    for (uint c = 0u; c < kWalkVecs; ++c) dots[c] = vec4(0.0);
    if (i < pc.size.x) {
        float m = imageLoad(inv_diag, int(i)).x;
        for (uint c = 0u; c < vecs; ++c) {
            uint at = i * vecs + c;
            vec4 alpha = vec4(scalars[4u * c].value.y, scalars[4u * c + 1u].value.y, scalars[4u * c + 2u].value.y,
                              scalars[4u * c + 3u].value.y);
            vec4 xi = x[at];
            uint keep = pc.mode.z >> (4u * c);
            if ((keep & 15u) != 0u) best[at] = mix(best[at], xi, vec4(bvec4(keep & 1u, keep & 2u, keep & 4u, keep & 8u)));
            x[at] = xi + alpha * imageLoad(p, int(at));
            vec4 ri = r[at] - alpha * imageLoad(ap, int(at));
            r[at] = ri;
            vec4 zi = m * ri;
            z[at] = zi;
            dots[c] = ri * zi;
        }
    }
    WALK_STORE_PARTIALS(dots, partials);
}

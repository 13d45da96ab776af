#version 450
// Conjugate gradient start: r = b - A x, z = r / diag, p = z, and the partial dots r . z (mode.x
// = 0) or b . b / diag (mode.x = 3: the size of the problem, what the residual is measured against).
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"

layout(local_size_x = 256) in;
// Reads through texel buffers: gathered in vector code on CPU drivers (walk_apply.comp).
layout(binding = 0, rgba32f) readonly uniform imageBuffer b;
layout(binding = 1, rgba32f) readonly uniform imageBuffer ax;
layout(binding = 2, r32f) readonly uniform imageBuffer inv_diag;
layout(std430, binding = 3) writeonly buffer R { vec4 r[]; };
layout(std430, binding = 4) writeonly buffer Z { vec4 z[]; };
layout(std430, binding = 5) writeonly buffer P { vec4 p[]; };
layout(std430, binding = 6) writeonly buffer Partials { vec4 partials[]; };
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
            const vec4 bi = imageLoad(b, int(at));
            vec4 ri = m > 0.0 ? bi - imageLoad(ax, int(at)) : vec4(0.0);
            vec4 zi = m * ri;
            r[at] = ri;
            z[at] = zi;
            p[at] = zi;
            dots[c] = pc.mode.x == 3u ? bi * m * bi : ri * zi;
        }
    }
    WALK_STORE_PARTIALS(dots, partials);
}

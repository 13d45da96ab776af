#version 450
// Multigrid post-smoothing: one weighted-Jacobi sweep z = v + smoother (r - A v) after the
// coarse correction, the mirror of the pre-smoothing step (so the V-cycle is symmetric, as
// conjugate gradient needs); on the finest level (mode.x = 1) also the partial dots r . z.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"

layout(local_size_x = 256) in;
// Reads through texel buffers: gathered in vector code on CPU drivers (walk_apply.comp).
layout(binding = 0, r32ui) readonly uniform uimageBuffer rows;
layout(binding = 1, r32ui) readonly uniform uimageBuffer columns;
layout(binding = 2, r32f) readonly uniform imageBuffer weights;
layout(binding = 3, r32f) readonly uniform imageBuffer diagonal;
layout(binding = 4, r32f) readonly uniform imageBuffer smoother;  // 0: out of the system
layout(binding = 5, rgba32f) readonly uniform imageBuffer r;
layout(binding = 6, rgba32f) readonly uniform imageBuffer v;
layout(std430, binding = 7) writeonly buffer Z { vec4 z[]; };
layout(std430, binding = 8) writeonly buffer Partials { vec4 partials[]; };
layout(push_constant) uniform Push { WalkCyclePush pc; };
#include "segment/walk_common.glsl"

void main() {
    uint vecs = WALK_VECS;
    uint i = pg_global_index();
    vec4 dots[kWalkVecs];
    for (uint c = 0u; c < kWalkVecs; ++c) dots[c] = vec4(0.0);
    if (i < pc.size.x) {
        float m = imageLoad(smoother, int(i)).x;
        vec4 acc[kWalkVecs], ri[kWalkVecs], vi[kWalkVecs];
        for (uint c = 0u; c < vecs; ++c) {
            acc[c] = vec4(0.0);
            ri[c] = imageLoad(r, int(i * vecs + c));
            vi[c] = imageLoad(v, int(i * vecs + c));
        }
        if (m > 0.0) {
            float d = imageLoad(diagonal, int(i)).x;
            for (uint c = 0u; c < vecs; ++c) acc[c] = ri[c] - d * vi[c];
            const uint end = imageLoad(rows, int(i + 1u)).x;
            for (uint s = imageLoad(rows, int(i)).x; s < end; ++s) {
                uint j = imageLoad(columns, int(s)).x;
                float w = imageLoad(weights, int(s)).x;
                for (uint c = 0u; c < vecs; ++c) acc[c] += w * imageLoad(v, int(j * vecs + c));
            }
        }
        for (uint c = 0u; c < vecs; ++c) {
            vec4 zi = vi[c] + m * acc[c];
            z[i * vecs + c] = zi;
            dots[c] = ri[c] * zi;
        }
    }
    if (pc.mode.x == 1u) WALK_STORE_PARTIALS(dots, partials);
}

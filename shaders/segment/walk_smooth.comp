#version 450
// Multigrid post-smoothing: one weighted-Jacobi sweep z = v + smoother (r - A v) after the
// coarse correction, the mirror of the pre-smoothing step (so the V-cycle is symmetric, as
// conjugate gradient needs); on the finest level (mode.x = 1) also the partial dots r . z.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Rows { uint rows[]; };
layout(std430, binding = 1) readonly buffer Columns { uint columns[]; };
layout(std430, binding = 2) readonly buffer Weights { float weights[]; };
layout(std430, binding = 3) readonly buffer Diagonal { float diagonal[]; };
layout(std430, binding = 4) readonly buffer Smoother { float smoother[]; };  // 0: out of the system
layout(std430, binding = 5) readonly buffer R { vec4 r[]; };
layout(std430, binding = 6) readonly buffer V { vec4 v[]; };
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
        float m = smoother[i];
        vec4 acc[kWalkVecs];
        for (uint c = 0u; c < vecs; ++c) acc[c] = vec4(0.0);
        if (m > 0.0) {
            float d = diagonal[i];
            for (uint c = 0u; c < vecs; ++c) acc[c] = r[i * vecs + c] - d * v[i * vecs + c];
            for (uint s = rows[i]; s < rows[i + 1u]; ++s) {
                uint j = columns[s];
                float w = weights[s];
                for (uint c = 0u; c < vecs; ++c) acc[c] += w * v[j * vecs + c];
            }
        }
        for (uint c = 0u; c < vecs; ++c) {
            vec4 zi = v[i * vecs + c] + m * acc[c];
            z[i * vecs + c] = zi;
            dots[c] = r[i * vecs + c] * zi;
        }
    }
    if (pc.mode.x == 1u) WALK_STORE_PARTIALS(dots, partials);
}

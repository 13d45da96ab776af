#version 450
// y[r, c] = x[r, c] * s[r]: drop path's per-point keep mask (0 or 1/keep) and its gradient.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/grad_shared.glsl"
layout(local_size_x = PG_GRAD_THREADS) in;
layout(std430, binding = 0) readonly buffer X { float x[]; };
layout(std430, binding = 1) readonly buffer S { float s[]; };
layout(std430, binding = 2) writeonly buffer Y { float y[]; };
layout(push_constant) uniform PushBlock { ScaleRowsPush pc; };

void main() {
    const uint i = pg_global_index();
    if (i >= pc.n) return;
    y[i] = x[i] * s[i / pc.channels];
}

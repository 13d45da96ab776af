#version 450
// y[r, c] = x[r, c] * s[r]: drop path's per-point keep mask (0 or 1/keep) and its gradient.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/grad_shared.glsl"
layout(local_size_x = PG_GRAD_THREADS) in;
// Reads through texel buffers: gathered in vector code on CPU drivers, where a storage buffer
// load at an address that differs between lanes is a loop over the lanes.
layout(binding = 0, r32f) readonly uniform imageBuffer x;
layout(binding = 1, r32f) readonly uniform imageBuffer s;
layout(std430, binding = 2) writeonly buffer Y { float y[]; };
layout(push_constant) uniform PushBlock { ScaleRowsPush pc; };

void main() {
    const uint i = pg_global_index();
    if (i >= pc.n) return;
    y[i] = imageLoad(x, int(i)).x * imageLoad(s, int(i / pc.channels)).x;
}

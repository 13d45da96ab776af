#version 450
// GELU backward, exact erf form: dx = dy * (Phi(x) + x * phi(x)), Phi the normal CDF (through
// erfc, accurate for x < 0 too) and phi its density.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/erf.glsl"
#include "nn/grad_shared.glsl"
layout(local_size_x = PG_GRAD_THREADS) in;
// Reads through texel buffers: gathered in vector code on CPU drivers, where a storage buffer
// load at an address that differs between lanes is a loop over the lanes.
layout(binding = 0, r32f) readonly uniform imageBuffer x;
layout(binding = 1, r32f) readonly uniform imageBuffer dy;
layout(std430, binding = 2) writeonly buffer DxBuf { float dx[]; };
layout(push_constant) uniform PushBlock { RowsPush pc; };  // rows = element count

void main() {
    const uint i = pg_global_index();
    if (i >= pc.rows) return;
    const float v = imageLoad(x, int(i)).x;
    const float cdf = 0.5 * pg_erfc(-0.70710678118654752 * v);
    const float vc = clamp(v, -20.0, 20.0);  // keeps v*v finite; exp underflows to 0 beyond
    const float pdf = 0.39894228040143268 * exp(-0.5 * vc * vc);
    dx[i] = imageLoad(dy, int(i)).x * (cdf + v * pdf);
}

#version 450
// Split-K epilogue of nn/linear: y[m,n] = bias[n] + residual[m,n] + sum_s partial[s,m,n], then
// GELU when asked.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/erf.glsl"
#include "nn/gemm_shared.glsl"
layout(local_size_x = 256) in;
// Reads through texel buffers: gathered in vector code on CPU drivers, where a storage buffer
// load at an address that differs between lanes is a loop over the lanes.
layout(binding = 0, r32f) readonly uniform imageBuffer part;
layout(binding = 1, r32f) readonly uniform imageBuffer bias;
layout(binding = 2, r32f) readonly uniform imageBuffer res;
layout(std430, binding = 3) writeonly buffer YBuf { float y[]; };
layout(push_constant) uniform PushBlock { GemmReducePush pc; };

void main() {
    const uint i = pg_global_index();
    if (i >= pc.M * pc.N) return;
    float v = 0.0;
    for (uint s = 0u; s < pc.splits; ++s) v += imageLoad(part, int(s * pc.M * pc.N + i)).x;
    if ((pc.flags & PG_GEMM_BIAS) != 0u) v += imageLoad(bias, int(i % pc.N)).x;
    if ((pc.flags & PG_GEMM_RESIDUAL) != 0u) v += imageLoad(res, int(i)).x;
    if ((pc.flags & PG_GEMM_GELU) != 0u) v = pg_gelu(v);
    y[i] = v;
}

#version 450
// Split-K epilogue of nn/linear: y[m,n] = bias[n] + residual[m,n] + sum_s partial[s,m,n], then
// GELU when asked.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/erf.glsl"
#include "nn/gemm_shared.glsl"
layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer PartBuf { float part[]; };
layout(std430, binding = 1) readonly buffer BiasBuf { float bias[]; };
layout(std430, binding = 2) readonly buffer ResBuf { float res[]; };
layout(std430, binding = 3) writeonly buffer YBuf { float y[]; };
layout(push_constant) uniform PushBlock { GemmReducePush pc; };

void main() {
    const uint i = pg_global_index();
    if (i >= pc.M * pc.N) return;
    float v = 0.0;
    for (uint s = 0u; s < pc.splits; ++s) v += part[s * pc.M * pc.N + i];
    if ((pc.flags & PG_GEMM_BIAS) != 0u) v += bias[i % pc.N];
    if ((pc.flags & PG_GEMM_RESIDUAL) != 0u) v += res[i];
    if ((pc.flags & PG_GEMM_GELU) != 0u) v = pg_gelu(v);
    y[i] = v;
}

#version 450
// y[M, N] = bias or 0: the per-tap GEMMs of a rulebook convolution then add into y.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/conv_shared.glsl"
#include "nn/gemm_shared.glsl"
layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer BiasBuf { float bias[]; };
layout(std430, binding = 1) writeonly buffer YBuf { float y[]; };
layout(push_constant) uniform PushBlock { ConvInitPush pc; };

void main() {
    const uint i = pg_global_index();
    if (i >= pc.M * pc.N) return;
    y[i] = (pc.flags & PG_GEMM_BIAS) != 0u ? bias[i % pc.N] : 0.0;
}

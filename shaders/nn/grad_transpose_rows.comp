#version 450
// A window of rows of a GEMM operand, transposed: out[k, r] = A[m0 + r, k] for r < rows, with
// A[m, k] = x[m, k] (dense: taps = 1, cin = K) or x[nbr[m, k / cin], k % cin] (gathered, 0 for
// -1), and 0 for rows at or past M (padding). It turns the weight gradient dyᵀ·A into the
// forward's GEMM, linear(dyᵀ, Aᵀ). nn/grad_transpose_rows8 is the same on 8x8 blocks.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/grad_shared.glsl"
layout(local_size_x = PG_GRAD_THREADS) in;
layout(std430, binding = 0) readonly buffer XBuf { float x[]; };
layout(std430, binding = 1) readonly buffer NbrBuf { int nbr[]; };
layout(std430, binding = 2) writeonly buffer OutBuf { float outv[]; };
layout(push_constant) uniform PushBlock { TransposeRowsPush pc; };

void main() {
    const uint i = pg_global_index();
    if (i >= pc.K * pc.rows) return;
    const uint k = i / pc.rows, m = pc.m0 + i % pc.rows;
    float v = 0.0;
    if (m < pc.M && pc.gather == 0u) {
        v = x[m * pc.K + k];
    } else if (m < pc.M) {
        const uint t = k / pc.cin;
        const int j = nbr[m * pc.taps + t];
        if (j >= 0) v = x[uint(j) * pc.cin + (k - t * pc.cin)];
    }
    outv[i] = v;
}

#version 450
// Training-mode BatchNorm backward, elementwise over x [rows, cols]: with the batch statistics
// mean, var (biased), inv = 1/sqrt(var + eps), sum_dy[c] = sum_r dy and sum_dev[c] =
// sum_r dy * (x - mean): dx = gamma * inv * (dy - sum_dy / M - (x - mean) * inv^2 * sum_dev / M).
// Row 0 also writes dgamma[c] = sum_dev[c] * inv.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/grad_shared.glsl"
layout(local_size_x = PG_GRAD_THREADS) in;
layout(std430, binding = 0) readonly buffer XBuf { float x[]; };
layout(std430, binding = 1) readonly buffer DyBuf { float dy[]; };
layout(std430, binding = 2) readonly buffer MeanBuf { float mean[]; };
layout(std430, binding = 3) readonly buffer VarBuf { float var[]; };
layout(std430, binding = 4) readonly buffer GammaBuf { float gamma[]; };
layout(std430, binding = 5) readonly buffer SumDyBuf { float sum_dy[]; };
layout(std430, binding = 6) readonly buffer SumDevBuf { float sum_dev[]; };
layout(std430, binding = 7) writeonly buffer DxBuf { float dx[]; };
layout(std430, binding = 8) writeonly buffer DgammaBuf { float dgamma[]; };
layout(push_constant) uniform PushBlock { RowsPush pc; };

void main() {
    const uint i = pg_global_index();
    if (i >= pc.rows * pc.cols) return;
    const uint c = i % pc.cols;
    const float inv = 1.0 / sqrt(var[c] + pc.eps);
    const float n = float(pc.rows);
    const float dev = x[i] - mean[c];
    dx[i] = gamma[c] * inv * ((dy[i] - sum_dy[c] / n) - dev * (inv * inv) * (sum_dev[c] / n));
    if (i < pc.cols) dgamma[c] = sum_dev[c] * inv;
}

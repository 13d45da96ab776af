#version 450
// LayerNorm backward over the c channels of each row: with xhat = (x - mean) * inv and
// g = dy * gamma, dx = inv * (g - mean(g) - xhat * mean(g * xhat)). Mean and variance are
// recomputed two-pass as the forward does (shifted by x[row, 0]); the row's shift, mean (of
// x - shift) and inv go to stats [rows, 3] for the dgamma column sums. One invocation per row.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/grad_shared.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer XBuf { float x[]; };
layout(std430, binding = 1) readonly buffer GammaBuf { float gamma[]; };
layout(std430, binding = 2) readonly buffer DyBuf { float dy[]; };
layout(std430, binding = 3) writeonly buffer DxBuf { float dx[]; };
layout(std430, binding = 4) writeonly buffer StatsBuf { float stats[]; };
layout(push_constant) uniform PushBlock { RowsPush pc; };

void main() {
    const uint r = pg_global_index();
    if (r >= pc.rows) return;
    const uint base = r * pc.cols;
    const float n = float(pc.cols);
    const float shift = x[base];
    float s = 0.0;
    for (uint i = 0u; i < pc.cols; ++i) s += x[base + i] - shift;
    const float mean = s / n;  // of x - shift
    float q = 0.0;
    for (uint i = 0u; i < pc.cols; ++i) {
        const float d = (x[base + i] - shift) - mean;
        q += d * d;
    }
    const float inv = 1.0 / sqrt(q / n + pc.eps);

    float sg = 0.0, sgx = 0.0;
    for (uint i = 0u; i < pc.cols; ++i) {
        const float g = dy[base + i] * gamma[i];
        sg += g;
        sgx += g * (((x[base + i] - shift) - mean) * inv);
    }
    const float mg = sg / n, mgx = sgx / n;
    for (uint i = 0u; i < pc.cols; ++i) {
        const float xhat = ((x[base + i] - shift) - mean) * inv;
        dx[base + i] = inv * ((dy[base + i] * gamma[i] - mg) - xhat * mgx);
    }
    stats[3u * r] = shift;
    stats[3u * r + 1u] = mean;
    stats[3u * r + 2u] = inv;
}

#version 450
// LayerNorm backward over the c channels of each row: with xhat = (x - mean) * inv and
// g = dy * gamma, dx = inv * (g - mean(g) - xhat * mean(g * xhat)). Mean and variance are
// recomputed two-pass as the forward does (shifted by x[row, 0]); the row's shift, mean (of
// x - shift) and inv go to stats [rows, 3] for the dgamma column sums. One invocation per row.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/grad_shared.glsl"
layout(local_size_x = 64) in;
// Reads through texel buffers: a load in a loop is one vector gather, not a loop over the lanes
// (spirv_bindings.h).
layout(binding = 0, r32f) readonly uniform imageBuffer x_;
layout(binding = 1, r32f) readonly uniform imageBuffer gamma_;
layout(binding = 2, r32f) readonly uniform imageBuffer dy_;
#define X(i) imageLoad(x_, int(i)).x
#define GAMMA(i) imageLoad(gamma_, int(i)).x
#define DY(i) imageLoad(dy_, int(i)).x
layout(std430, binding = 3) writeonly buffer DxBuf { float dx[]; };
layout(std430, binding = 4) writeonly buffer StatsBuf { float stats[]; };
layout(push_constant) uniform PushBlock { RowsPush pc; };

void main() {
    const uint r = pg_global_index();
    if (r >= pc.rows) return;
    const uint base = r * pc.cols;
    const float n = float(pc.cols);
    const float shift = X(base);
    float s = 0.0;
    for (uint i = 0u; i < pc.cols; ++i) s += X(base + i) - shift;
    const float mean = s / n;  // of x - shift
    float q = 0.0;
    for (uint i = 0u; i < pc.cols; ++i) {
        const float d = (X(base + i) - shift) - mean;
        q += d * d;
    }
    const float inv = 1.0 / sqrt(q / n + pc.eps);

    float sg = 0.0, sgx = 0.0;
    for (uint i = 0u; i < pc.cols; ++i) {
        const float g = DY(base + i) * GAMMA(i);
        sg += g;
        sgx += g * (((X(base + i) - shift) - mean) * inv);
    }
    const float mg = sg / n, mgx = sgx / n;
    for (uint i = 0u; i < pc.cols; ++i) {
        const float xhat = ((X(base + i) - shift) - mean) * inv;
        dx[base + i] = inv * ((DY(base + i) * GAMMA(i) - mg) - xhat * mgx);
    }
    stats[3u * r] = shift;
    stats[3u * r + 1u] = mean;
    stats[3u * r + 2u] = inv;
}

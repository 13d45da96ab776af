#version 450
// Column sums in chunks of rows: part[chunk, c] = sum over the chunk's rows, in row order, of
// the mode's term (grad_shared.glsl). One invocation per (chunk, column); neighbours take
// neighbouring columns, so each row is read contiguously.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/grad_shared.glsl"
layout(local_size_x = PG_GRAD_THREADS) in;
layout(std430, binding = 0) readonly buffer ABuf { float a[]; };
layout(std430, binding = 1) readonly buffer BBuf { float b[]; };
layout(std430, binding = 2) readonly buffer VBuf { float v[]; };
layout(std430, binding = 3) writeonly buffer PartBuf { float part[]; };
layout(push_constant) uniform PushBlock { ColumnPartialsPush pc; };

void main() {
    const uint i = pg_global_index();
    const uint chunks = (pc.rows + pc.rows_per_chunk - 1u) / pc.rows_per_chunk;
    if (i >= chunks * pc.cols) return;
    const uint chunk = i / pc.cols, c = i % pc.cols;
    const uint r0 = chunk * pc.rows_per_chunk, r1 = min(r0 + pc.rows_per_chunk, pc.rows);
    float s = 0.0;
    if (pc.mode == PG_COLSUM_PLAIN) {
        for (uint r = r0; r < r1; ++r) s += a[r * pc.cols + c];
    } else if (pc.mode == PG_COLSUM_SQDEV) {
        const float mean = v[c];
        for (uint r = r0; r < r1; ++r) {
            const float d = a[r * pc.cols + c] - mean;
            s += d * d;
        }
    } else if (pc.mode == PG_COLSUM_DEV) {
        const float mean = v[c];
        for (uint r = r0; r < r1; ++r) s += a[r * pc.cols + c] * (b[r * pc.cols + c] - mean);
    } else {
        // The row statistics as the LayerNorm forward applies them: shift first, exact for values near it.
        for (uint r = r0; r < r1; ++r)
            s += a[r * pc.cols + c] * (((b[r * pc.cols + c] - v[3u * r]) - v[3u * r + 1u]) * v[3u * r + 2u]);
    }
    part[i] = s;
}

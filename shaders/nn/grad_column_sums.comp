#version 450
// nn/grad_column_partials and nn/grad_sum_partials in one pass, for CPU devices: one
// invocation per column sums each chunk of rows, then the chunks in order, the same float
// operations in the same order (bit-identical). Only `cols` invocations, each walking every
// row: right where a dispatch's fixed cost outweighs the rows' work (lavapipe), wrong on GPUs.
// Workgroups of 8 (one SIMD group on lavapipe) spread the columns over the cores.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/grad_shared.glsl"
#include "nn/grad_column_term.glsl"
layout(local_size_x = PG_COLSUM_THREADS) in;
layout(std430, binding = 3) writeonly buffer OutBuf { float outv[]; };
layout(push_constant) uniform PushBlock { ColumnSumsPush pc; };

void main() {
    const uint c = pg_global_index();
    if (c >= pc.cols) return;
    const uint chunks = (pc.rows + pc.rows_per_chunk - 1u) / pc.rows_per_chunk;
    float s = 0.0;
    for (uint chunk = 0u; chunk < chunks; ++chunk)
        s += column_chunk_sum(pc.mode, pc.rows, pc.cols, pc.rows_per_chunk, chunk, c);
    outv[c] = s * pc.scale;
}

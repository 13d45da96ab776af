#version 450
// Column sums in chunks of rows: part[chunk, c] = sum over the chunk's rows, in row order, of
// the mode's term (grad_shared.glsl). One invocation per (chunk, column); neighbours take
// neighbouring columns, so each row is read contiguously. nn/grad_sum_partials adds the chunks.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/grad_shared.glsl"
#include "nn/grad_column_term.glsl"
layout(local_size_x = PG_GRAD_THREADS) in;
layout(std430, binding = 3) writeonly buffer PartBuf { float part[]; };
layout(push_constant) uniform PushBlock { ColumnPartialsPush pc; };

void main() {
    const uint i = pg_global_index();
    const uint chunks = (pc.rows + pc.rows_per_chunk - 1u) / pc.rows_per_chunk;
    if (i >= chunks * pc.cols) return;
    part[i] = column_chunk_sum(pc.mode, pc.rows, pc.cols, pc.rows_per_chunk, i / pc.cols, i % pc.cols);
}

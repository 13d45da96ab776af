// The column reductions' shared part (nn/grad_column_partials, nn/grad_column_sums): bindings
// and the sum of one chunk of rows of a column, in row order, of the mode's term
// (grad_shared.glsl). The reads go through texel buffers: a load in a loop is a loop over the
// lanes from a storage buffer on CPU drivers, one vector gather from a texel buffer.
#ifndef PG_GRAD_COLUMN_TERM_GLSL
#define PG_GRAD_COLUMN_TERM_GLSL
layout(binding = 0, r32f) readonly uniform imageBuffer a_texels;
layout(binding = 1, r32f) readonly uniform imageBuffer b_texels;
layout(binding = 2, r32f) readonly uniform imageBuffer v_texels;
#define A(i) imageLoad(a_texels, int(i)).x
#define B(i) imageLoad(b_texels, int(i)).x
#define V(i) imageLoad(v_texels, int(i)).x

float column_chunk_sum(uint mode, uint rows, uint cols, uint rows_per_chunk, uint chunk, uint c) {
    const uint r0 = chunk * rows_per_chunk, r1 = min(r0 + rows_per_chunk, rows);
    float s = 0.0;
    if (mode == PG_COLSUM_PLAIN) {
        for (uint r = r0; r < r1; ++r) s += A(r * cols + c);
    } else if (mode == PG_COLSUM_SQDEV) {
        const float mean = V(c);
        for (uint r = r0; r < r1; ++r) {
            const float d = A(r * cols + c) - mean;
            s += d * d;
        }
    } else if (mode == PG_COLSUM_DEV) {
        const float mean = V(c);
        for (uint r = r0; r < r1; ++r) s += A(r * cols + c) * (B(r * cols + c) - mean);
    } else {
        // The row statistics as the LayerNorm forward applies them: shift first, exact for values near it.
        for (uint r = r0; r < r1; ++r)
            s += A(r * cols + c) * (((B(r * cols + c) - V(3u * r)) - V(3u * r + 1u)) * V(3u * r + 2u));
    }
    return s;
}
#endif

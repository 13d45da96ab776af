// GEMM for GPUs: y[M,N] = A[M,K] . W[N,K]^T (+ bias + residual, then GELU), A dense or gathered
// (gemm_shared.glsl). A workgroup of 256 computes a 64x64 tile of y, each invocation a 4x4
// block held in registers; the depth is walked in slices of 16 staged in shared memory.
// With PG_GEMM_PARTIAL the workgroups of split s cover depth [s*k0, (s+1)*k0) and write raw
// partial sums to y[s] for nn/linear_reduce to add up (split-K, for few tiles and a deep K).
// With RULEBOOK defined to 1 the rows are the pairs of one tap of a sparse-convolution rulebook
// (tap k0 / cin, depth its cin columns of W; dispatched indirectly over its pairs) and each
// adds its product into y at its output row.
#extension GL_EXT_control_flow_attributes : require
#include "common/dispatch.glsl"
#include "nn/erf.glsl"
#include "nn/gemm_shared.glsl"
#ifndef RULEBOOK
#define RULEBOOK 0
#endif

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer XBuf { float x[]; };
layout(std430, binding = 1) readonly buffer WBuf { float w[]; };
layout(std430, binding = 2) readonly buffer BiasBuf { float bias[]; };
layout(std430, binding = 3) readonly buffer ResBuf { float res[]; };
#if RULEBOOK
layout(std430, binding = 4) buffer YBuf { float y[]; };
layout(std430, binding = 5) readonly buffer PairBuf { uvec2 pairs[]; };  // [taps][M]: (output row, input row)
layout(std430, binding = 6) readonly buffer CountBuf { uint counts[]; };  // pairs per tap
#else
layout(std430, binding = 4) writeonly buffer YBuf { float y[]; };
layout(std430, binding = 5) readonly buffer NbrBuf { int nbr[]; };
#endif
layout(push_constant) uniform PushBlock { GemmPush pc; };

// [k][row / 4] as vec4 over 4 consecutive rows (columns for Ws): the inner loop reads one
// vec4 of each per depth step.
shared vec4 As[PG_TILE_K][PG_TILE_M / 4];
shared vec4 Ws[PG_TILE_K][PG_TILE_N / 4];

void main() {
    const uint t = gl_LocalInvocationIndex;
    const uint g = pg_group_index();
#if RULEBOOK
    const uint tap = pc.k0 / pc.cin, first = tap * pc.M, rows = counts[tap];
    const uint tile = g;
    const uint kbeg = pc.k0, kend = pc.k0 + pc.cin;
#else
    const uint rows = pc.M;
    const uint tiles = ((pc.M + PG_TILE_M - 1u) / PG_TILE_M) * pc.col_tiles;
    const uint split = g / tiles, tile = g % tiles;
    const bool partial = (pc.flags & PG_GEMM_PARTIAL) != 0u;
    const uint kbeg = partial ? split * pc.k0 : 0u;
    const uint kend = partial ? min(kbeg + pc.k0, pc.K) : pc.K;
    const bool gather = (pc.flags & PG_GEMM_GATHER) != 0u;
#endif
    const uint m0 = (tile / pc.col_tiles) * PG_TILE_M, n0 = (tile % pc.col_tiles) * PG_TILE_N;

    // Loader role: row (or weight row) lr of the tile, depth quad kq of the slice.
    const uint lr = t / 4u, kq = (t % 4u) * 4u;
    const uint lm = min(m0 + lr, max(rows, 1u) - 1u), ln = n0 + lr;
#if RULEBOOK
    const uint lj = pairs[first + lm].y;
#endif
    // Compute role: rows ty*4.., columns tx*4.. of the tile.
    const uint tx = t % 16u, ty = t / 16u;

    vec4 acc[4];
    [[unroll]] for (uint i = 0u; i < 4u; ++i) acc[i] = vec4(0.0);

    for (uint k0 = kbeg; k0 < kend; k0 += PG_TILE_K) {
        float av[4], wv[4];
        [[unroll]] for (uint i = 0u; i < 4u; ++i) {
            const uint k = k0 + kq + i;
            float a = 0.0, b = 0.0;
            if (k < kend) {
#if RULEBOOK
                a = x[lj * pc.cin + k - kbeg];
#else
                int j = int(lm);
                uint c = k;
                if (gather) {
                    j = nbr[lm * pc.taps + k / pc.cin];
                    c = k % pc.cin;
                }
                if (j >= 0) a = x[uint(j) * pc.cin + c];
#endif
                if (ln < pc.N) b = w[ln * pc.K + k];
            }
            av[i] = a;
            wv[i] = b;
        }
        barrier();  // the previous slice is consumed
        [[unroll]] for (uint i = 0u; i < 4u; ++i) {
            As[kq + i][lr / 4u][lr % 4u] = av[i];
            Ws[kq + i][lr / 4u][lr % 4u] = wv[i];
        }
        barrier();
        [[unroll]] for (uint kk = 0u; kk < PG_TILE_K; ++kk) {
            const vec4 a = As[kk][ty], b = Ws[kk][tx];
            acc[0] += a.x * b;
            acc[1] += a.y * b;
            acc[2] += a.z * b;
            acc[3] += a.w * b;
        }
    }

    [[unroll]] for (uint i = 0u; i < 4u; ++i) {
        const uint m = m0 + ty * 4u + i;
        if (m >= rows) break;
#if RULEBOOK
        const uint o = pairs[first + m].x;
#endif
        [[unroll]] for (uint j = 0u; j < 4u; ++j) {
            const uint n = n0 + tx * 4u + j;
            if (n >= pc.N) break;
            float v = acc[i][j];
#if RULEBOOK
            y[o * pc.N + n] += v;
#else
            if (partial) {
                y[(split * pc.M + m) * pc.N + n] = v;
            } else {
                if ((pc.flags & PG_GEMM_BIAS) != 0u) v += bias[n];
                if ((pc.flags & PG_GEMM_RESIDUAL) != 0u) v += res[m * pc.N + n];
                if ((pc.flags & PG_GEMM_GELU) != 0u) v = pg_gelu(v);
                y[m * pc.N + n] = v;
            }
#endif
        }
    }
}

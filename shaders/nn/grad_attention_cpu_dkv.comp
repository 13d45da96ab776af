#version 450
// Backward of window attention for CPU drivers, per key (nn/train/grad_attention.cpp): sums over
// the queries whose windows hold the key, with P and D from grad_attention_cpu_dq's (lse, D):
//   dv = sum_i P_i dout_i,  dk = scale * sum_i P_i (dout_i . v - D_i) q_i.
// A workgroup's keys are a block of one K-aligned range w of positions. Window w's queries are
// that same range, and its keys are too unless w is the cloud's last (pulled back) window; keys
// in the cloud's final K positions are also keys of that last window. So: window w's queries
// when w is not the last, then the last window's queries for the keys it holds, in that fixed
// order, as grad_attention_dkv sums them. Built per head dimension (PG_ATTN_D).
#extension GL_GOOGLE_include_directive : require
#include "nn/grad_attention_cpu.glsl"

layout(std430, binding = 3) readonly buffer Stats { uint64_t stats64[]; };  // [H, N]: (base-2 lse, D)

vec4 key[ROWS * D4], val[ROWS * D4], dk[ROWS * D4], dv[ROWS * D4];

// Adds the queries at cloud-local positions [q0, q1) to the keys whose row is at least `from`.
void add_queries(WindowBlock wb, int q0, int q1, int from) {
    const uint t = gl_LocalInvocationIndex;
    float take[ROWS];
    [[unroll]] for (uint r = 0u; r < ROWS; ++r) take[r] = wb.p0 + int(r * THREADS + t) >= from ? 1.0 : 0.0;
    [[dont_unroll]] for (int i0 = q0; i0 < q1; i0 += GROUP) {
        vec4 qg[GROUP * D4], gg[GROUP * D4];
        vec2 st[GROUP];
        [[unroll]] for (uint ii = 0u; ii < GROUP; ++ii) {
            const int p = wb.base + min(i0 + int(ii), q1 - 1);
            vec4 x[D4];
            load_part(wb.head, p, PART_Q, x);
            [[unroll]] for (uint d = 0u; d < D4; ++d) qg[ii * D4 + d] = x[d];
            load_part(wb.head, p, PART_G, x);
            [[unroll]] for (uint d = 0u; d < D4; ++d) gg[ii * D4 + d] = x[d];
            st[ii] = uintBitsToFloat(unpackUint2x32(stats64[wb.head * pc.rows + uint(p)]));
        }
        [[unroll]] for (uint r = 0u; r < ROWS; ++r) {
            [[unroll]] for (uint ii = 0u; ii < GROUP; ++ii) {
                vec4 kq = key[r * D4] * qg[ii * D4], vg = val[r * D4] * gg[ii * D4];
                [[unroll]] for (uint d = 1u; d < D4; ++d) {
                    kq = fma(key[r * D4 + d], qg[ii * D4 + d], kq);
                    vg = fma(val[r * D4 + d], gg[ii * D4 + d], vg);
                }
                const float p = i0 + int(ii) < q1 ? take[r] * exp2((kq.x + kq.y) + (kq.z + kq.w) - st[ii].x) : 0.0;
                const float ds = p * ((vg.x + vg.y) + (vg.z + vg.w) - st[ii].y);
                [[unroll]] for (uint d = 0u; d < D4; ++d) {
                    dv[r * D4 + d] = fma(vec4(p), gg[ii * D4 + d], dv[r * D4 + d]);
                    dk[r * D4 + d] = fma(vec4(ds), qg[ii * D4 + d], dk[r * D4 + d]);
                }
            }
        }
    }
}

void main() {
    WindowBlock wb;
    if (!window_block(wb)) return;
    const uint t = gl_LocalInvocationIndex;
    [[unroll]] for (uint r = 0u; r < ROWS; ++r) {
        // Lanes past the block compute a copy of its last key and write nothing.
        const int p = wb.base + min(wb.p0 + int(r * THREADS + t), wb.p1 - 1);
        vec4 x[D4];
        load_part(wb.head, p, PART_K, x);
        [[unroll]] for (uint d = 0u; d < D4; ++d) key[r * D4 + d] = x[d] * pc.scale2;
        load_part(wb.head, p, PART_V, x);
        [[unroll]] for (uint d = 0u; d < D4; ++d) {
            val[r * D4 + d] = x[d];
            dk[r * D4 + d] = vec4(0.0);
            dv[r * D4 + d] = vec4(0.0);
        }
    }
    const int K = int(pc.window);
    const int last = (wb.n - 1) / K;  // the pulled-back window
    if (wb.w < last) add_queries(wb, wb.w * K, (wb.w + 1) * K, wb.p0);
    // The last window's keys are the cloud's final K positions (all of it when n <= K).
    const int from = wb.n - K;
    if (wb.p1 - 1 >= from) add_queries(wb, last * K, wb.n, from);

    [[unroll]] for (uint r = 0u; r < ROWS; ++r) {
        const int at = wb.p0 + int(r * THREADS + t);
        if (at >= wb.p1) continue;
        vec4 x[D4];
        [[unroll]] for (uint d = 0u; d < D4; ++d) x[d] = dk[r * D4 + d];
        store_part(wb.base + at, wb.head, 1u, x, pc.scale);
        [[unroll]] for (uint d = 0u; d < D4; ++d) x[d] = dv[r * D4 + d];
        store_part(wb.base + at, wb.head, 2u, x, 1.0);
    }
}

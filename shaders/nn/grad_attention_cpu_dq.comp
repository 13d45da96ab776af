#version 450
// Backward of window attention for CPU drivers, per query (nn/train/grad_attention.cpp): recomputes
// the softmax over the query's window (logsumexp and out) in a first sweep, then
//   D = dout . out,  dq = scale * sum_j P_j (dout . v_j - D) k_j
// in a second, and keeps (lse, D) for the key pass. Built per head dimension (PG_ATTN_D).
#extension GL_GOOGLE_include_directive : require
#include "nn/grad_attention_cpu.glsl"

layout(std430, binding = 3) writeonly buffer Stats { vec2 stats[]; };  // [H, N]: (base-2 lse, D)

// Keys and values j0 .. j0 + GROUP of the window starting at key0; past count, its last one.
void load_keys(uint head, int key0, int j0, int count, out vec4 kg[GROUP * D4], out vec4 vg[GROUP * D4]) {
    [[unroll]] for (uint jj = 0u; jj < GROUP; ++jj) {
        vec4 x[D4];
        load_part(head, key0 + min(j0 + int(jj), count - 1), PART_K, x);
        [[unroll]] for (uint d = 0u; d < D4; ++d) kg[jj * D4 + d] = x[d];
        load_part(head, key0 + min(j0 + int(jj), count - 1), PART_V, x);
        [[unroll]] for (uint d = 0u; d < D4; ++d) vg[jj * D4 + d] = x[d];
    }
}

void main() {
    WindowBlock wb;
    if (!window_block(wb)) return;
    const uint t = gl_LocalInvocationIndex;
    const int K = int(pc.window);
    const int key0 = wb.base + max(0, min(wb.w * K, wb.n - K)), count = min(K, wb.n);

    vec4 q[ROWS * D4], go[ROWS * D4], acc[ROWS * D4];
    float m[ROWS], l[ROWS];
    [[unroll]] for (uint r = 0u; r < ROWS; ++r) {
        // Lanes past the block compute a copy of its last query and write nothing.
        const int p = wb.base + min(wb.p0 + int(r * THREADS + t), wb.p1 - 1);
        vec4 x[D4];
        load_part(wb.head, p, PART_Q, x);
        [[unroll]] for (uint d = 0u; d < D4; ++d) q[r * D4 + d] = x[d] * pc.scale2;
        load_part(wb.head, p, PART_G, x);
        [[unroll]] for (uint d = 0u; d < D4; ++d) {
            go[r * D4 + d] = x[d];
            acc[r * D4 + d] = vec4(0.0);
        }
        m[r] = kNone;
        l[r] = 0.0;
    }

    // Sweep 1: the softmax (online, a rescale per group of keys) and out = P v.
    [[dont_unroll]] for (int j0 = 0; j0 < count; j0 += GROUP) {
        vec4 kg[GROUP * D4], vg[GROUP * D4];
        load_keys(wb.head, key0, j0, count, kg, vg);
        [[unroll]] for (uint r = 0u; r < ROWS; ++r) {
            float s[GROUP];
            [[unroll]] for (uint jj = 0u; jj < GROUP; ++jj) {
                vec4 part = q[r * D4] * kg[jj * D4];
                [[unroll]] for (uint d = 1u; d < D4; ++d) part = fma(q[r * D4 + d], kg[jj * D4 + d], part);
                s[jj] = j0 + int(jj) < count ? (part.x + part.y) + (part.z + part.w) : kNone;
            }
            const float alpha = softmax_group(m[r], l[r], s);
            [[unroll]] for (uint d = 0u; d < D4; ++d) {
                vec4 a = acc[r * D4 + d] * alpha;
                [[unroll]] for (uint jj = 0u; jj < GROUP; ++jj) a = fma(vec4(s[jj]), vg[jj * D4 + d], a);
                acc[r * D4 + d] = a;
            }
        }
    }
    float lse[ROWS], dsum[ROWS];
    [[unroll]] for (uint r = 0u; r < ROWS; ++r) {
        lse[r] = m[r] + log2(l[r]);
        vec4 s = go[r * D4] * acc[r * D4];
        [[unroll]] for (uint d = 1u; d < D4; ++d) s = fma(go[r * D4 + d], acc[r * D4 + d], s);
        dsum[r] = ((s.x + s.y) + (s.z + s.w)) / l[r];
        [[unroll]] for (uint d = 0u; d < D4; ++d) acc[r * D4 + d] = vec4(0.0);
    }

    // Sweep 2: dq = sum_j P_j (dout . v_j - D) k_j, in key order.
    [[dont_unroll]] for (int j0 = 0; j0 < count; j0 += GROUP) {
        vec4 kg[GROUP * D4], vg[GROUP * D4];
        load_keys(wb.head, key0, j0, count, kg, vg);
        [[unroll]] for (uint r = 0u; r < ROWS; ++r) {
            [[unroll]] for (uint jj = 0u; jj < GROUP; ++jj) {
                vec4 qk = q[r * D4] * kg[jj * D4], gv = go[r * D4] * vg[jj * D4];
                [[unroll]] for (uint d = 1u; d < D4; ++d) {
                    qk = fma(q[r * D4 + d], kg[jj * D4 + d], qk);
                    gv = fma(go[r * D4 + d], vg[jj * D4 + d], gv);
                }
                const float p = j0 + int(jj) < count ? exp2((qk.x + qk.y) + (qk.z + qk.w) - lse[r]) : 0.0;
                const float ds = p * ((gv.x + gv.y) + (gv.z + gv.w) - dsum[r]);
                [[unroll]] for (uint d = 0u; d < D4; ++d) acc[r * D4 + d] = fma(vec4(ds), kg[jj * D4 + d], acc[r * D4 + d]);
            }
        }
    }

    [[unroll]] for (uint r = 0u; r < ROWS; ++r) {
        const int at = wb.p0 + int(r * THREADS + t);
        if (at >= wb.p1) continue;
        stats[wb.head * pc.rows + uint(wb.base + at)] = vec2(lse[r], dsum[r]);
        vec4 x[D4];
        [[unroll]] for (uint d = 0u; d < D4; ++d) x[d] = acc[r * D4 + d];
        store_part(wb.base + at, wb.head, 0u, x, pc.scale);
    }
}

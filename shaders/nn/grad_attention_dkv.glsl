// Backward of window attention, per key (one invocation per head and position): sums over the
// queries whose windows hold the key, with P and D from grad_attention_dq's (lse, D):
//   dv = sum_i P_i dout_i,  dk = scale * sum_i P_i (dout_i . v - D_i) q_i.
// Windows start at multiples of K except a cloud's last, pulled back to end at n, so a key is
// in at most two windows: its own K-aligned one (unless that is the last) and the last one
// (when it lies in the cloud's final K positions). They are summed in that fixed order.
#include "nn/grad_attention_common.glsl"

layout(std430, binding = 3) readonly buffer Stats { vec2 stats[]; };  // [H, N]: (base-2 lse, D)
layout(std430, binding = 4) writeonly buffer Dqkv { vec4 dqkv[]; };  // [N, 3C]

vec4 key[D4], val[D4], dk[D4], dv[D4];

// Adds the queries at positions [q0, q1).
void add_queries(Site s, int q0, int q1) {
    for (int i = q0; i < q1; ++i) {
        const uint qr = row(s, i);
        const vec2 st = stats[s.head * pc.rows + uint(i)];
        const float p = exp2(dot_row(key, qr + PART_Q) * pc.scale2 - st.x);
        const float ds = p * (dot_row(val, qr + PART_G) - st.y);
        [[unroll]] for (int c = 0; c < D4; ++c) {
            dv[c] += p * g[qr + PART_G + c];
            dk[c] += ds * g[qr + PART_Q + c];
        }
    }
}

void main() {
    Site s;
    if (!site(s)) return;
    const uint me = row(s, s.pos);
    [[unroll]] for (int c = 0; c < D4; ++c) {
        key[c] = g[me + PART_K + c];
        val[c] = g[me + PART_V + c];
        dk[c] = vec4(0.0);
        dv[c] = vec4(0.0);
    }
    const int K = int(pc.window);
    const int l = s.pos - s.base;
    if (s.n <= K) {
        add_queries(s, s.base, s.base + s.n);
    } else {
        const int last = (s.n - 1) / K;  // index of the pulled-back window
        if (l / K < last) add_queries(s, s.base + l / K * K, s.base + (l / K + 1) * K);
        if (l >= s.n - K) add_queries(s, s.base + last * K, s.base + s.n);
    }
    const uint dk_at = dqkv_at(s, 1u), dv_at = dqkv_at(s, 2u);
    [[unroll]] for (int c = 0; c < D4; ++c) {
        dqkv[dk_at + c] = dk[c] * pc.scale;
        dqkv[dv_at + c] = dv[c];
    }
}

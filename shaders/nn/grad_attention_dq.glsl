// Backward of window attention, per query (one invocation per head and position): recomputes
// the softmax over the query's window (logsumexp and out) in a first sweep, then
//   D = dout . out,  dq = scale * sum_j P_j (dout . v_j - D) k_j
// in a second, and keeps (lse, D) for the key pass (grad_attention_dkv).
#include "nn/grad_attention_common.glsl"

layout(std430, binding = 3) writeonly buffer Stats { vec2 stats[]; };  // [H, N]: (base-2 lse, D)
layout(std430, binding = 4) writeonly buffer Dqkv { vec4 dqkv[]; };   // [N, 3C]

void main() {
    Site s;
    if (!site(s)) return;
    const int K = int(pc.window);
    const int l = s.pos - s.base;
    const int first = s.base + (s.n <= K ? 0 : min(l / K * K, s.n - K));
    const int count = min(K, s.n);
    const uint me = row(s, s.pos);
    vec4 q[D4], go[D4], acc[D4];
    [[unroll]] for (int c = 0; c < D4; ++c) {
        q[c] = g[me + PART_Q + c];
        go[c] = g[me + PART_G + c];
        acc[c] = vec4(0.0);
    }
    // Online softmax; -3e38 is below any logit yet finite, so exp2(m - x) is 0 at the start.
    float m = -3.0e38, sum = 0.0;
    for (int j = 0; j < count; ++j) {
        const uint kr = row(s, first + j);
        const float x = dot_row(q, kr + PART_K) * pc.scale2;
        const float mx = max(m, x);
        const float alpha = exp2(m - mx), w = exp2(x - mx);
        sum = sum * alpha + w;
        [[unroll]] for (int c = 0; c < D4; ++c) acc[c] = acc[c] * alpha + w * g[kr + PART_V + c];
        m = mx;
    }
    const float lse = m + log2(sum);
    float dsum = 0.0;
    [[unroll]] for (int c = 0; c < D4; ++c) dsum += dot(go[c], acc[c]);
    dsum /= sum;
    stats[s.head * pc.rows + uint(s.pos)] = vec2(lse, dsum);

    [[unroll]] for (int c = 0; c < D4; ++c) acc[c] = vec4(0.0);
    for (int j = 0; j < count; ++j) {
        const uint kr = row(s, first + j);
        const float p = exp2(dot_row(q, kr + PART_K) * pc.scale2 - lse);
        const float ds = p * (dot_row(go, kr + PART_V) - dsum);
        [[unroll]] for (int c = 0; c < D4; ++c) acc[c] += ds * g[kr + PART_K + c];
    }
    const uint dq_at = dqkv_at(s, 0u);
    [[unroll]] for (int c = 0; c < D4; ++c) dqkv[dq_at + c] = acc[c] * pc.scale;
}

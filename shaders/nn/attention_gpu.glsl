// Serialized window attention (PTv3, no RPE), flash style, for GPUs: a workgroup takes a block
// of serialized positions of one cloud and one head; each invocation keeps its queries and
// their running softmax state in registers while the window's keys and values (contiguous in
// the gathered kv buffer) stream through shared memory in tiles.
// The including shader defines PG_ATTN_D (head dimension, a multiple of 4).
#extension GL_EXT_control_flow_attributes : require
#include "nn/attention_config.glsl"

#define D4 (PG_ATTN_D / 4)
#define ROWS PG_ATTN_GPU_ROWS
#define THREADS PG_ATTN_GPU_THREADS
#define BLOCK (THREADS * ROWS)
#define TILE PG_ATTN_TILE
#define GROUP PG_ATTN_GROUP

layout(local_size_x = THREADS) in;
layout(std430, binding = 0) readonly buffer Qkv { vec4 qkv[]; };  // [N, 3C]: q | k | v
layout(std430, binding = 4) readonly buffer Kv { vec4 kv[]; };  // [H, N, 2D] (attention_gather)
#include "nn/attention_common.glsl"

shared vec4 tile_k[TILE * D4];
shared vec4 tile_v[TILE * D4];

void main() {
    QueryBlock qb;
    if (!query_block(qb)) return;
    const int span = min(int(pc.window), qb.n);
    const uint t = gl_LocalInvocationIndex;
    const uint stride = 3u * pc.channels / 4u;
    const uint q_col = qb.head * D4;
    const uint kv_head = qb.head * pc.rows;

    for (int w = qb.q0 / int(pc.window); w * int(pc.window) < qb.q1; ++w) {
        const int s0 = max(qb.q0, w * int(pc.window)), s1 = min(qb.q1, (w + 1) * int(pc.window));
        const int key0 = window_start(qb, w);

        vec4 q[ROWS * D4], acc[ROWS * D4];
        float m[ROWS], l[ROWS];
        [[unroll]] for (uint r = 0u; r < ROWS; ++r) {
            // Lanes past the window compute a copy of its first query and write nothing.
            const int at = clamp(qb.q0 + int(r * THREADS + t), s0, s1 - 1);
            const uint row = point_at(qb.base + at) * stride + q_col;
            [[unroll]] for (uint d = 0u; d < D4; ++d) {
                q[r * D4 + d] = qkv[row + d] * pc.scale;
                acc[r * D4 + d] = vec4(0.0);
            }
            m[r] = kNone;
            l[r] = 0.0;
        }

        for (int k0 = 0; k0 < span; k0 += TILE) {
            const int kn = min(TILE, span - k0);
            barrier();  // the previous tile is consumed
            for (uint e = t; e < TILE * D4; e += THREADS) {
                const uint j = e / D4, d = e % D4;
                vec4 kj = vec4(0.0), vj = vec4(0.0);
                if (int(j) < kn) {
                    const uint at = (kv_head + uint(key0 + k0) + j) * (2u * D4) + d;
                    kj = kv[at];
                    vj = kv[at + D4];
                }
                tile_k[e] = kj;
                tile_v[e] = vj;
            }
            barrier();

            // Groups of keys share one softmax rescale.
            for (int j0 = 0; j0 < kn; j0 += GROUP) {
                [[unroll]] for (uint r = 0u; r < ROWS; ++r) {
                    float s[GROUP];
                    [[unroll]] for (uint jj = 0u; jj < GROUP; ++jj) {
                        vec4 part = q[r * D4] * tile_k[(uint(j0) + jj) * D4];
                        [[unroll]] for (uint d = 1u; d < D4; ++d)
                            part = fma(q[r * D4 + d], tile_k[(uint(j0) + jj) * D4 + d], part);
                        s[jj] = j0 + int(jj) < kn ? (part.x + part.y) + (part.z + part.w) : kNone;
                    }
                    const float alpha = softmax_group(m[r], l[r], s);
                    [[unroll]] for (uint d = 0u; d < D4; ++d) {
                        vec4 a = acc[r * D4 + d] * alpha;
                        [[unroll]] for (uint jj = 0u; jj < GROUP; ++jj)
                            a = fma(vec4(s[jj]), tile_v[(uint(j0) + jj) * D4 + d], a);
                        acc[r * D4 + d] = a;
                    }
                }
            }
        }

        [[unroll]] for (uint r = 0u; r < ROWS; ++r) {
            const int at = qb.q0 + int(r * THREADS + t);
            if (at < s0 || at >= s1) continue;
            const uint row = point_at(qb.base + at) * (pc.channels / 4u) + qb.head * D4;
            const float inv = 1.0 / l[r];
            [[unroll]] for (uint d = 0u; d < D4; ++d) result[row + d] = acc[r * D4 + d] * inv;
        }
    }
}

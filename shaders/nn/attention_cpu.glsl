// Serialized window attention (PTv3, no RPE) for CPU drivers such as lavapipe, where every
// memory load is a loop over the SIMD lanes, even when all lanes read the same address. So
// there is no shared-memory staging (a second round of such loops): each invocation reads the
// window's keys and values straight from the gathered kv buffer, 64 bits per component (twice
// the floats per lane-loop iteration of a vec4), and every loaded key and value serves its
// ROWS queries.
// The including shader defines PG_ATTN_D (head dimension, a multiple of 8).
#extension GL_EXT_control_flow_attributes : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "nn/attention_config.glsl"
#include "nn/pack8.glsl"

#define D4 (PG_ATTN_D / 4)
#define D8 (PG_ATTN_D / 8)
#define ROWS PG_ATTN_CPU_ROWS(PG_ATTN_D)
#define THREADS PG_ATTN_CPU_THREADS
#define BLOCK (THREADS * ROWS)
#define GROUP PG_ATTN_GROUP

layout(local_size_x = THREADS) in;
// 8 floats per element: fewer, wider components per lane-loop iteration.
layout(std430, binding = 0) readonly buffer Qkv { u64vec4 qkv[]; };  // [N, 3C]
// Keys and values through a texel buffer: all lanes read the same key, and a load inside a loop
// is a loop over the lanes from a storage buffer but one vector gather from a texel buffer.
layout(binding = 4, rgba32f) readonly uniform imageBuffer kv4;  // [H, N, 2D] (attention_gather)
#include "nn/attention_common.glsl"

void main() {
    QueryBlock qb;
    if (!query_block(qb)) return;
    const int span = min(int(pc.window), qb.n);
    const uint t = gl_LocalInvocationIndex;
    const uint q_col = qb.head * D8;
    const uint kv_head = qb.head * pc.rows;

    for (int w = qb.q0 / int(pc.window); w * int(pc.window) < qb.q1; ++w) {
        const int s0 = max(qb.q0, w * int(pc.window)), s1 = min(qb.q1, (w + 1) * int(pc.window));
        const int key0 = window_start(qb, w);

        vec4 q[ROWS * D4], acc[ROWS * D4];
        float m[ROWS], l[ROWS];
        [[unroll]] for (uint r = 0u; r < ROWS; ++r) {
            // Lanes past the window compute a copy of its first query and write nothing.
            const int at = clamp(qb.q0 + int(r * THREADS + t), s0, s1 - 1);
            const uint row = point_at(qb.base + at) * (3u * pc.channels / 8u) + q_col;
            [[unroll]] for (uint i = 0u; i < D8; ++i) {
                unpack8(qkv[row + i], q[r * D4 + 2u * i], q[r * D4 + 2u * i + 1u]);
                q[r * D4 + 2u * i] *= pc.scale;
                q[r * D4 + 2u * i + 1u] *= pc.scale;
            }
            [[unroll]] for (uint d = 0u; d < D4; ++d) acc[r * D4 + d] = vec4(0.0);
            m[r] = kNone;
            l[r] = 0.0;
        }

        // Groups of keys share one softmax rescale; keys past the window repeat its last one
        // and are masked out.
        [[dont_unroll]] for (int j0 = 0; j0 < span; j0 += GROUP) {
            vec4 kg[GROUP * D4], vg[GROUP * D4];
            [[unroll]] for (uint jj = 0u; jj < GROUP; ++jj) {
                const uint at = (kv_head + uint(key0 + min(j0 + int(jj), span - 1))) * (2u * D8);
                [[unroll]] for (uint i = 0u; i < D8; ++i) {
                    kg[jj * D4 + 2u * i] = imageLoad(kv4, int(2u * (at + i)));
                    kg[jj * D4 + 2u * i + 1u] = imageLoad(kv4, int(2u * (at + i) + 1u));
                    vg[jj * D4 + 2u * i] = imageLoad(kv4, int(2u * (at + D8 + i)));
                    vg[jj * D4 + 2u * i + 1u] = imageLoad(kv4, int(2u * (at + D8 + i) + 1u));
                }
            }
            [[unroll]] for (uint r = 0u; r < ROWS; ++r) {
                float s[GROUP];
                [[unroll]] for (uint jj = 0u; jj < GROUP; ++jj) {
                    vec4 part = q[r * D4] * kg[jj * D4];
                    [[unroll]] for (uint d = 1u; d < D4; ++d) part = fma(q[r * D4 + d], kg[jj * D4 + d], part);
                    s[jj] = j0 + int(jj) < span ? (part.x + part.y) + (part.z + part.w) : kNone;
                }
                const float alpha = softmax_group(m[r], l[r], s);
                [[unroll]] for (uint d = 0u; d < D4; ++d) {
                    vec4 a = acc[r * D4 + d] * alpha;
                    [[unroll]] for (uint jj = 0u; jj < GROUP; ++jj) a = fma(vec4(s[jj]), vg[jj * D4 + d], a);
                    acc[r * D4 + d] = a;
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

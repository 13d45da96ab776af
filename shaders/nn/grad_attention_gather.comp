#version 450
// Per head, in serialized order: g[h][p] = (q, k, v, dout) of the point at position p, 4 * D
// floats, so the backward kernels read each window as one contiguous run.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/grad_attention_config.glsl"

layout(local_size_x = PG_GRAD_ATTN_THREADS) in;
layout(std430, binding = 0) readonly buffer Qkv { vec4 qkv[]; };    // [N, 3C]
layout(std430, binding = 1) readonly buffer Order { int order[]; };
layout(std430, binding = 2) readonly buffer Dout { vec4 dout[]; };  // [N, C]
layout(std430, binding = 3) writeonly buffer G { vec4 g[]; };       // [H, N, 4D]
layout(push_constant) uniform PushBlock { GradAttentionPush pc; };

void main() {
    const uint i = pg_global_index();
    const uint d4 = pc.head_dim / 4u;
    if (i >= pc.heads * pc.rows * 4u * d4) return;
    const uint c = i % (4u * d4);
    const uint hp = i / (4u * d4);  // h * N + p
    const uint h = hp / pc.rows, p = hp % pc.rows;
    const uint point = uint(clamp(order[p], 0, int(pc.rows) - 1));
    const uint part = c / d4, col = h * d4 + c % d4;
    const uint c4 = pc.channels / 4u;
    g[i] = part < 3u ? qkv[point * 3u * c4 + part * c4 + col] : dout[point * c4 + col];
}

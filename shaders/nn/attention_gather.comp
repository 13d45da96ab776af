#version 450
// Keys and values in serialized order, head-major: kv[h][p] = (k, v) of head h of the point at
// serialized position p, 2 * head_dim floats. The attention kernels then read each window's
// keys as one contiguous run instead of rows scattered through qkv.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/attention_config.glsl"

layout(local_size_x = PG_ATTN_GATHER_THREADS) in;
layout(std430, binding = 0) readonly buffer Qkv { vec4 qkv[]; };  // [N, 3C]
layout(std430, binding = 1) readonly buffer Order { int order[]; };
layout(std430, binding = 2) writeonly buffer Kv { vec4 kv[]; };  // [H, N, 2D]
layout(push_constant) uniform PushBlock { AttentionPush pc; };

void main() {
    const uint i = pg_global_index();
    const uint d4 = pc.head_dim / 4u;
    const uint per_point = 2u * d4;
    if (i >= pc.heads * pc.rows * per_point) return;
    const uint c = i % per_point;
    const uint hp = i / per_point;  // h * N + p
    const uint h = hp / pc.rows, p = hp % pc.rows;
    const uint point = uint(clamp(order[p], 0, int(pc.rows) - 1));
    // k for c < d4, v after it.
    const uint col = (c < d4 ? pc.channels : 2u * pc.channels) / 4u + h * d4 + c % d4;
    kv[i] = qkv[point * (3u * pc.channels / 4u) + col];
}

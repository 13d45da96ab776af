// Shared by the attention backward kernels: the gathered inputs, where an invocation's
// (head, position) lies, and the window rule. The including shader defines PG_ATTN_D first.
#extension GL_EXT_control_flow_attributes : require
#include "common/dispatch.glsl"
#include "nn/grad_attention_config.glsl"

#define D4 (PG_ATTN_D / 4)
// Offsets of q, k, v, dout inside a gathered row of 4 * D4 vec4s.
#define PART_Q 0u
#define PART_K uint(D4)
#define PART_V uint(2 * D4)
#define PART_G uint(3 * D4)

layout(local_size_x = PG_GRAD_ATTN_THREADS) in;
layout(std430, binding = 0) readonly buffer G { vec4 g[]; };  // [H, N, 4D] (grad_attention_gather)
layout(std430, binding = 1) readonly buffer Order { int order[]; };
layout(std430, binding = 2) readonly buffer Offsets { int offsets[]; };
layout(push_constant) uniform PushBlock { GradAttentionPush pc; };

struct Site {
    uint head;
    int pos;   // serialized position
    int base;  // the cloud's first position
    int n;     // the cloud's positions
};

// Invocation i is head i / N at position i % N; false past the end.
bool site(out Site s) {
    const uint i = pg_global_index();
    if (i >= pc.heads * pc.rows) return false;
    s.head = i / pc.rows;
    s.pos = int(i % pc.rows);
    int lo = 0, hi = int(pc.clouds) - 1;  // the last cloud with offsets[b] <= pos
    while (lo < hi) {
        const int mid = (lo + hi + 1) >> 1;
        if (offsets[mid] <= s.pos) lo = mid;
        else hi = mid - 1;
    }
    s.base = offsets[lo];
    s.n = offsets[lo + 1] - s.base;
    return s.pos >= s.base && s.pos < s.base + s.n;  // false only for malformed offsets
}

// First vec4 of the gathered row of position p (clamped into bounds) for the site's head.
uint row(Site s, int p) { return (s.head * pc.rows + uint(clamp(p, 0, int(pc.rows) - 1))) * uint(4 * D4); }

// First vec4 of the site's point in dqkv [N, 3C] for part 0 (q), 1 (k) or 2 (v).
uint dqkv_at(Site s, uint part) {
    const uint point = uint(clamp(order[s.pos], 0, int(pc.rows) - 1));
    const uint c4 = pc.channels / 4u;
    return point * 3u * c4 + part * c4 + s.head * uint(D4);
}

float dot_row(vec4 a[D4], uint at) {
    float s = 0.0;
    [[unroll]] for (int c = 0; c < D4; ++c) s += dot(a[c], g[at + c]);
    return s;
}

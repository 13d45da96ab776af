// Shared by the window-attention backward kernels for CPU drivers (grad_attention_cpu_dq,
// grad_attention_cpu_dkv): like the forward's attention_cpu, each invocation keeps ROWS
// positions of one window in registers, so that every key, value, query or output gradient it
// loads (a per-lane loop on lavapipe, 64 bits per component here) serves ROWS of them. A
// workgroup takes one block of BLOCK positions inside one window, so no lane computes for a
// window it does not belong to (the forward's blocks may straddle windows). The including
// shader defines PG_ATTN_D (head dimension, a multiple of 8).
#extension GL_EXT_control_flow_attributes : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "common/dispatch.glsl"
#include "nn/attention_config.glsl"
#include "nn/pack8.glsl"
#include "nn/attention_softmax.glsl"
#include "nn/grad_attention_config.glsl"

#define D4 (PG_ATTN_D / 4)
#define D8 (PG_ATTN_D / 8)
#define THREADS PG_ATTN_CPU_THREADS
#define ROWS PG_GRAD_ATTN_CPU_ROWS(PG_ATTN_D)
#define BLOCK (THREADS * ROWS)
#define GROUP PG_ATTN_GROUP
// u64vec4 elements of a gathered row [q | k | v | dout], 8 floats each.
#define PART_Q 0u
#define PART_K uint(D8)
#define PART_V uint(2 * D8)
#define PART_G uint(3 * D8)

layout(local_size_x = THREADS) in;
// Through a texel buffer: loads inside the key loops (the same row for every lane) are loops over
// the lanes from a storage buffer, one vector gather from a texel buffer (attention_cpu.glsl).
layout(binding = 0, rgba32f) readonly uniform imageBuffer g4;  // [H, N, 4D] (grad_attention_gather)
layout(std430, binding = 1) readonly buffer Order { int order[]; };
layout(std430, binding = 2) readonly buffer Offsets { int offsets[]; };
layout(std430, binding = 4) writeonly buffer Dqkv { u64vec4 dqkv8[]; };  // [N, 3C]
layout(push_constant) uniform PushBlock { GradAttentionPush pc; };

// Loads part `part` of the gathered row at serialized position p into x[0 .. D4).
void load_part(uint head, int p, uint part, out vec4 x[D4]) {
    const uint at = (head * pc.rows + uint(clamp(p, 0, int(pc.rows) - 1))) * (4u * D8) + part;
    [[unroll]] for (uint i = 0u; i < D4; ++i) x[i] = imageLoad(g4, int(2u * at + i));
}

float dot_d(vec4 a[D4], vec4 b[D4]) {
    vec4 s = a[0] * b[0];
    [[unroll]] for (uint d = 1u; d < D4; ++d) s = fma(a[d], b[d], s);
    return (s.x + s.y) + (s.z + s.w);
}

// Stores x * f as part `part` (0 q, 1 k, 2 v) of the point at serialized position p in dqkv.
void store_part(int p, uint head, uint part, vec4 x[D4], float f) {
    const uint point = uint(clamp(order[clamp(p, 0, int(pc.rows) - 1)], 0, int(pc.rows) - 1));
    const uint at = (point * 3u * pc.channels + part * pc.channels + head * uint(PG_ATTN_D)) / 8u;
    [[unroll]] for (uint i = 0u; i < D8; ++i) dqkv8[at + i] = pack8(x[2u * i] * f, x[2u * i + 1u] * f);
}

// One workgroup's share: positions [p0, p1) of window w of a cloud (cloud-local positions).
struct WindowBlock {
    uint head;
    int base;  // serialized position of the cloud's first point
    int n;     // the cloud's points
    int w;     // window: positions [w*K, min((w+1)*K, n)) are its queries
    int p0, p1;
};

// Windows are numbered cloud after cloud: cloud b's first is floor(offsets[b] / K) + b, an upper
// bound on the windows of the clouds before it. Workgroup g is head g % H, then window
// (g / H) / subs, block (g / H) % subs of it. False for the gaps of the numbering.
bool window_block(out WindowBlock wb) {
    const uint g = pg_group_index();
    const int K = int(pc.window);
    wb.head = g % pc.heads;
    const int window = int((g / pc.heads) / pc.subs), sub = int((g / pc.heads) % pc.subs);
    if (window >= int(pc.windows)) return false;
    int lo = 0, hi = int(pc.clouds) - 1;
    while (lo < hi) {
        const int mid = (lo + hi + 1) >> 1;
        if (offsets[mid] / K + mid <= window) lo = mid;
        else hi = mid - 1;
    }
    wb.base = offsets[lo];
    wb.n = offsets[lo + 1] - wb.base;
    wb.w = window - (wb.base / K + lo);
    wb.p0 = wb.w * K + sub * BLOCK;
    wb.p1 = min(min(wb.w * K + K, wb.n), wb.p0 + BLOCK);
    return wb.w >= 0 && wb.p0 < wb.p1;
}

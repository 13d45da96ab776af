// Shared by the attention kernels: bindings other than qkv and the gathered keys/values, which
// block of queries a workgroup owns, and the online softmax step. The including kernel defines
// BLOCK (queries per workgroup) first and enables GL_EXT_control_flow_attributes.
#include "common/dispatch.glsl"
#include "nn/attention_config.glsl"
#include "nn/attention_softmax.glsl"

layout(std430, binding = 1) readonly buffer Order { int order[]; };
layout(std430, binding = 2) readonly buffer Offsets { int offsets[]; };
layout(std430, binding = 3) writeonly buffer Out { vec4 result[]; };  // [N, C]
layout(push_constant) uniform PushBlock { AttentionPush pc; };

// The point at serialized position p, clamped so malformed offsets never read out of bounds.
uint point_at(int p) {
    const int last = int(pc.rows) - 1;
    return uint(clamp(order[clamp(p, 0, last)], 0, last));
}

// Query blocks are numbered cloud after cloud; cloud b's first one is floor(offsets[b] /
// BLOCK) + b, an upper bound on the blocks of the clouds before it (at most one gap per cloud).
int first_block(int b) { return offsets[b] / BLOCK + b; }

struct QueryBlock {
    uint head;
    int base;  // serialized position of the cloud's first point
    int n;     // points in the cloud
    int q0;    // the block's cloud-local positions: [q0, q1)
    int q1;
};

// This workgroup's block; false for the gaps of the numbering (the whole group returns).
bool query_block(out QueryBlock qb) {
    const uint g = pg_group_index();
    qb.head = g % pc.heads;
    const int block = int(g / pc.heads);
    if (block >= int(pc.chunks)) return false;
    int lo = 0, hi = int(pc.clouds) - 1;
    while (lo < hi) {
        const int mid = (lo + hi + 1) >> 1;
        if (first_block(mid) <= block) lo = mid;
        else hi = mid - 1;
    }
    qb.base = offsets[lo];
    qb.n = offsets[lo + 1] - qb.base;
    qb.q0 = (block - first_block(lo)) * BLOCK;
    qb.q1 = min(qb.q0 + BLOCK, qb.n);
    return qb.q0 >= 0 && qb.q0 < qb.n;
}

// Windows start at multiples of the patch size except the last one of a cloud, which is pulled
// back to end at n; queries [w*K, (w+1)*K) share window w. A block spans several windows only
// when BLOCK does not divide the patch size. Returns the serialized position of window w's
// first key.
int window_start(QueryBlock qb, int w) { return qb.base + max(0, min(w * int(pc.window), qb.n - int(pc.window))); }

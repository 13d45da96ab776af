#version 450
// Rows of the cluster heads, shifted right: the next level's grid (width 3) or batch (width 1).
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/index_shared.glsl"
layout(local_size_x = PG_INDEX_THREADS) in;
layout(std430, binding = 0) readonly buffer Rows { int rows[]; };
layout(std430, binding = 1) readonly buffer Head { int head_[]; };
layout(std430, binding = 2) writeonly buffer Out { int out_rows[]; };
layout(push_constant) uniform PushBlock { ShiftPush pc; };

void main() {
    uint e = pg_global_index();
    if (e >= pc.n * pc.width) return;
    uint m = e / pc.width, a = e - m * pc.width;
    out_rows[e] = rows[uint(head_[m]) * pc.width + a] >> pc.shift;
}

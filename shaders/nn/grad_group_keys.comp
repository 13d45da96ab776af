#version 450
// Sort input for grouping gathered rows by their target: keys[r] = idx[r], values[r] = r.
// Indices outside [0, targets) become `targets`: they sort last and join no group.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/grad_shared.glsl"
layout(local_size_x = PG_GRAD_THREADS) in;
layout(std430, binding = 0) readonly buffer IdxBuf { int idx[]; };
layout(std430, binding = 1) writeonly buffer KeyBuf { uint keys[]; };
layout(std430, binding = 2) writeonly buffer ValueBuf { uint values[]; };
layout(push_constant) uniform PushBlock { GroupPush pc; };

void main() {
    const uint r = pg_global_index();
    if (r >= pc.rows) return;
    keys[r] = min(uint(idx[r]), pc.targets);  // a negative index wraps to a large uint
    values[r] = r;
}

#version 450
// inverse[order[j]] = j.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/index_shared.glsl"
layout(local_size_x = PG_INDEX_THREADS) in;
layout(std430, binding = 0) readonly buffer Order { uint order[]; };
layout(std430, binding = 1) writeonly buffer Inverse { uint inverse_[]; };
layout(push_constant) uniform PushBlock { CountPush pc; };

void main() {
    uint j = pg_global_index();
    if (j >= pc.n) return;
    inverse_[order[j]] = j;
}

#version 450
// 1 where a run of equal sorted keys starts, else 0 (the input of the run-numbering scan).
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/index_shared.glsl"
layout(local_size_x = PG_INDEX_THREADS) in;
layout(std430, binding = 0) readonly buffer Keys { uvec2 keys[]; };
layout(std430, binding = 1) writeonly buffer Starts { uint starts[]; };
layout(push_constant) uniform PushBlock { CountPush pc; };

void main() {
    uint j = pg_global_index();
    if (j >= pc.n) return;
    starts[j] = j == 0u || keys[j] != keys[j - 1u] ? 1u : 0u;
}

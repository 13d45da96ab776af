#version 450
// Mean over the counted rows: dlogits *= 1 / max(counted, 1) in place; invocation 0 writes
// loss[0] = sum of row losses / max(counted, 1) and info = (counted, bad) as uints.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/grad_shared.glsl"
layout(local_size_x = PG_GRAD_THREADS) in;
layout(std430, binding = 0) readonly buffer SumBuf { float sums[]; };
layout(std430, binding = 1) buffer DBuf { float dlogits[]; };
layout(std430, binding = 2) writeonly buffer LossBuf { float loss[]; };
layout(std430, binding = 3) writeonly buffer InfoBuf { uint info[]; };
layout(push_constant) uniform PushBlock { CrossEntropyPush pc; };

void main() {
    const uint i = pg_global_index();
    const float scale = 1.0 / max(sums[PG_CE_COUNTED], 1.0);
    if (i < pc.rows * pc.classes) dlogits[i] *= scale;
    if (i == 0u) {
        loss[0] = sums[PG_CE_LOSS] * scale;
        info[0] = uint(sums[PG_CE_COUNTED]);
        info[1] = uint(sums[PG_CE_BAD]);
    }
}

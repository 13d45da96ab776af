#version 450
// out[i] = scale * sum over s of part[s, i], in split order: the second stage of every
// deterministic reduction of nn/train.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/grad_shared.glsl"
layout(local_size_x = PG_GRAD_THREADS) in;
layout(std430, binding = 0) readonly buffer PartBuf { float part[]; };
layout(std430, binding = 1) writeonly buffer OutBuf { float outv[]; };
layout(push_constant) uniform PushBlock { SumPartialsPush pc; };

void main() {
    const uint i = pg_global_index();
    if (i >= pc.len) return;
    float s = 0.0;
    for (uint k = 0u; k < pc.splits; ++k) s += part[k * pc.len + i];
    outv[i] = s * pc.scale;
}

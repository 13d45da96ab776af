#version 450
// Backward of a gather through a permutation: dx[idx[r], c] = dy[r, c]. Every target is hit
// once, so there is no sum and no race.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/grad_shared.glsl"
layout(local_size_x = PG_GRAD_THREADS) in;
layout(std430, binding = 0) readonly buffer DyBuf { float dy[]; };
layout(std430, binding = 1) readonly buffer IdxBuf { int idx[]; };
layout(std430, binding = 2) writeonly buffer DxBuf { float dx[]; };
layout(push_constant) uniform PushBlock { GroupPush pc; };

void main() {
    const uint i = pg_global_index();
    if (i >= pc.rows * pc.cols) return;
    const uint r = i / pc.cols, c = i % pc.cols;
    dx[uint(idx[r]) * pc.cols + c] = dy[i];
}

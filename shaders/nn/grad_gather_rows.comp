#version 450
// Backward of a row gather, as a segmented sum: dx[p, c] = sum of dy[order[j], c] for j in
// [ptr[p], ptr[p+1]) (the rows gathered from p, ascending), 0 for rows never gathered.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/grad_shared.glsl"
layout(local_size_x = PG_GRAD_THREADS) in;
layout(std430, binding = 0) readonly buffer DyBuf { float dy[]; };
layout(std430, binding = 1) readonly buffer OrderBuf { int order[]; };
layout(std430, binding = 2) readonly buffer PtrBuf { int ptr[]; };
layout(std430, binding = 3) writeonly buffer DxBuf { float dx[]; };
layout(push_constant) uniform PushBlock { GroupPush pc; };

void main() {
    const uint i = pg_global_index();
    if (i >= pc.targets * pc.cols) return;
    const uint p = i / pc.cols, c = i % pc.cols;
    float s = 0.0;
    for (int j = ptr[p]; j < ptr[p + 1u]; ++j) s += dy[uint(order[j]) * pc.cols + c];
    dx[i] = s;
}

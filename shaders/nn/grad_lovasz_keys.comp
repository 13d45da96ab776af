#version 450
// Lovasz-softmax, pass 1: one sort key per (class c, row r) entry e = c * rows + r.
// Counted rows: key = (c << 32) | ~bits(error) with error = |[label == c] - p_c| >= 0, so an
// ascending stable sort puts each class's entries together, errors descending, ties by row.
// Rows not counted get class `classes`: they sort after every counted entry.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/grad_shared.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer LogitBuf { float logits[]; };
layout(std430, binding = 1) readonly buffer LabelBuf { int labels[]; };
layout(std430, binding = 2) writeonly buffer KeyBuf { uvec2 keys[]; };
layout(push_constant) uniform PushBlock { LovaszPush pc; };
#include "nn/grad_lovasz_softmax.glsl"

void main() {
    const uint e = pg_global_index();
    if (e >= pc.rows * pc.classes) return;
    const uint c = e / pc.rows, r = e - c * pc.rows;
    const int label = labels[r];
    if (!lovasz_counted(label)) {
        keys[e] = uvec2(0u, pc.classes);
        return;
    }
    const float error = abs((label == int(c) ? 1.0 : 0.0) - lovasz_probability(r, c));
    keys[e] = uvec2(~floatBitsToUint(error), c);
}

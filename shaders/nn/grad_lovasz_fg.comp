#version 450
// Lovasz-softmax, pass 2, per sorted entry j: fg[j] = 1 where the entry is its row's own class,
// for the prefix sum that counts foreground along each class's sorted run (fg[entries] = 0, so
// the scan also yields the total). counts[0] = the number of counted rows, n: the length of
// class 0's run, written by the entry that ends it (or by entry 0 when there is none).
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/grad_shared.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer LogitBuf { float logits[]; };
layout(std430, binding = 1) readonly buffer LabelBuf { int labels[]; };
layout(std430, binding = 2) readonly buffer OrderBuf { int order[]; };
layout(std430, binding = 3) writeonly buffer FgBuf { uint fg[]; };
layout(std430, binding = 4) writeonly buffer CountBuf { uint counts[]; };
layout(push_constant) uniform PushBlock { LovaszPush pc; };
#include "nn/grad_lovasz_softmax.glsl"

// The class an entry sorted under: its own, or `classes` for rows not counted.
uint sorted_class(uint j) {
    const uint e = uint(order[j]);
    return lovasz_counted(labels[e % pc.rows]) ? e / pc.rows : pc.classes;
}

void main() {
    const uint j = pg_global_index();
    const uint entries = pc.rows * pc.classes;
    if (j > entries) return;
    if (j == entries) {
        fg[j] = 0u;
        return;
    }
    const uint e = uint(order[j]);
    const uint c = e / pc.rows, r = e - c * pc.rows;
    fg[j] = labels[r] == int(c) ? 1u : 0u;
    const uint here = sorted_class(j);
    if (here == 0u && (j + 1u == entries || sorted_class(j + 1u) != 0u)) counts[0] = j + 1u;
    if (j == 0u && here != 0u) counts[0] = 0u;
}

#version 450
// CSR offsets of rows grouped by target from the sorted keys [rows]: ptr[p] = the first sorted
// position whose key is >= p, for p in [0, targets]. Invocation j in [0, rows] fills the
// targets between key[j-1] (exclusive) and key[j] (inclusive), with key[-1] = -1 and
// key[rows] = targets, so every entry is written once.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/grad_shared.glsl"
layout(local_size_x = PG_GRAD_THREADS) in;
layout(std430, binding = 0) readonly buffer KeyBuf { uint keys[]; };
layout(std430, binding = 1) writeonly buffer PtrBuf { int ptr[]; };
layout(push_constant) uniform PushBlock { GroupPush pc; };

void main() {
    const uint j = pg_global_index();
    if (j > pc.rows) return;
    // Keys past the targets (bad indices) are clamped there: those rows are left out of every group.
    const int lo = j == 0u ? -1 : int(min(keys[j - 1u], pc.targets));
    const int hi = j == pc.rows ? int(pc.targets) : int(min(keys[j], pc.targets));
    for (int p = lo + 1; p <= hi; ++p) ptr[p] = int(j);
}

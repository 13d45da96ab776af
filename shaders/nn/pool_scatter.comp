#version 450
// Clusters from the sorted keys: each run of equal keys is one cluster, numbered by the
// exclusive scan of run starts. Writes point -> cluster, the CSR offsets and the heads.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/index_shared.glsl"
layout(local_size_x = PG_INDEX_THREADS) in;
layout(std430, binding = 0) readonly buffer Keys { uvec2 keys[]; };
layout(std430, binding = 1) readonly buffer Starts { uint starts[]; };
layout(std430, binding = 2) readonly buffer Members { uint members[]; };
layout(std430, binding = 3) writeonly buffer Cluster { int cluster[]; };
layout(std430, binding = 4) writeonly buffer Ptr { int ptr[]; };
layout(std430, binding = 5) writeonly buffer Head { int head_[]; };
layout(push_constant) uniform PushBlock { CountPush pc; };

void main() {
    uint j = pg_global_index();
    if (j >= pc.n) return;
    bool head = j == 0u || keys[j] != keys[j - 1u];
    uint c = head ? starts[j] : starts[j] - 1u;
    cluster[members[j]] = int(c);
    if (head) {
        ptr[c] = int(j);
        head_[c] = int(members[j]);
    }
    if (j == pc.n - 1u) ptr[c + 1u] = int(pc.n);
}

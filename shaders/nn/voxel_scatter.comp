#version 450
// Voxels from the sorted keys: each run of equal keys is one voxel, numbered by the exclusive
// scan of run starts. Writes point -> voxel, and per voxel its first (lowest-index) point,
// grid and batch.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/index_shared.glsl"
layout(local_size_x = PG_INDEX_THREADS) in;
layout(std430, binding = 0) readonly buffer Keys { uvec2 keys[]; };
layout(std430, binding = 1) readonly buffer Starts { uint starts[]; };
layout(std430, binding = 2) readonly buffer Values { uint values[]; };
layout(std430, binding = 3) readonly buffer Grid { int grid[]; };
layout(std430, binding = 4) readonly buffer Batch { int batch[]; };
layout(std430, binding = 5) writeonly buffer Inverse { int inverse_[]; };
layout(std430, binding = 6) writeonly buffer First { int first[]; };
layout(std430, binding = 7) writeonly buffer VoxelGrid { int voxel_grid[]; };
layout(std430, binding = 8) writeonly buffer VoxelBatch { int voxel_batch[]; };
layout(push_constant) uniform PushBlock { CountPush pc; };

void main() {
    uint j = pg_global_index();
    if (j >= pc.n) return;
    bool head = j == 0u || keys[j] != keys[j - 1u];
    uint v = head ? starts[j] : starts[j] - 1u;
    uint p = values[j];
    inverse_[p] = int(v);
    if (head) {
        first[v] = int(p);
        for (uint a = 0u; a < 3u; ++a) voxel_grid[3u * v + a] = grid[3u * p + a];
        voxel_batch[v] = batch[p];
    }
}

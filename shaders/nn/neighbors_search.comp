#version 450
// Submanifold neighbour map. One invocation per (point, rx, ry): the k cells along z form one
// contiguous range of packed keys, so a single binary search in the sorted keys finds them all.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/index_shared.glsl"
#include "nn/index_key.glsl"
layout(local_size_x = PG_INDEX_THREADS) in;
layout(std430, binding = 0) readonly buffer Grid { int grid[]; };
layout(std430, binding = 1) readonly buffer Batch { int batch[]; };
layout(std430, binding = 2) readonly buffer Info { uint info[]; };
layout(std430, binding = 3) readonly buffer Keys { uvec2 keys[]; };
layout(std430, binding = 4) readonly buffer Values { uint values[]; };
layout(std430, binding = 5) writeonly buffer Nbr { int nbr[]; };
layout(push_constant) uniform PushBlock { NeighborPush pc; };

const uint kMaxKernel = 5u;

void main() {
    uint k = pc.kernel, kk = k * k;
    uint t = pg_global_index();
    if (t >= pc.n * kk) return;
    uint i = t / kk, r = t - i * kk, rx = r / k, ry = r - rx * k;
    int h = int(k / 2u);
    uvec4 maxima = uvec4(info[PG_INFO_MAX_X], info[PG_INFO_MAX_Y], info[PG_INFO_MAX_Z], info[PG_INFO_MAX_BATCH]);
    uvec4 w = grid_widths(maxima);
    ivec3 p = ivec3(grid[3u * i], grid[3u * i + 1u], grid[3u * i + 2u]);
    int nx = p.x + int(rx) - h, ny = p.y + int(ry) - h;

    int found[kMaxKernel] = int[kMaxKernel](-1, -1, -1, -1, -1);
    if (nx >= 0 && nx <= int(maxima.x) && ny >= 0 && ny <= int(maxima.y)) {
        int zlo = max(p.z - h, 0), zhi = min(p.z + h, int(maxima.z));
        uint b = uint(batch[i]);
        uvec2 lo = grid_key(w, uvec3(nx, ny, zlo), b), hi = grid_key(w, uvec3(nx, ny, zhi), b);
        // Lower bound of lo.
        uint first = 0u, count = pc.n;
        while (count > 0u) {
            uint half_ = count / 2u;
            if (key_less(keys[first + half_], lo)) {
                first += half_ + 1u;
                count -= half_ + 1u;
            } else {
                count = half_;
            }
        }
        uint zmask = w.z == 0u ? 0u : 0xFFFFFFFFu >> (32u - w.z);
        for (uint j = first; j < pc.n && !key_less(hi, keys[j]); ++j) {
            int rz = int(keys[j].x & zmask) - p.z + h;
            // Duplicate voxels: the stable sort puts the lowest point index first; keep it.
            if (found[rz] < 0) found[rz] = int(values[j]);
        }
    }
    uint base = (i * kk + r) * k;
    for (uint rz = 0u; rz < k; ++rz) nbr[base + rz] = found[rz];
}

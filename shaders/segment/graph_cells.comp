#version 450
// The uniform grid's cell key of every node (sorted next, so a cell's nodes are one run), and
// the node count of each row of cells along x (y + dims.y z; a prefix sum makes them row
// starts, so graph_knn finds a row's run without searching all the keys).
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"
#include "segment/graph_grid.glsl"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Pos { vec4 pos[]; };
layout(std430, binding = 1) writeonly buffer Keys { uint keys[]; };
layout(std430, binding = 2) writeonly buffer Values { uint values[]; };
layout(std430, binding = 3) buffer RowCounts { uint row_counts[]; };  // zeroed
layout(push_constant) uniform Push { GraphGridPush pc; };

void main() {
    uint i = pg_global_index();
    if (i >= pc.bits.z) return;
    ivec3 c = cell_of(pos[i].xyz, pc.origin, pc.dims);
    keys[i] = cell_key(c, pc.bits);
    values[i] = i;
    atomicAdd(row_counts[uint(c.y) + pc.dims.y * uint(c.z)], 1u);
}

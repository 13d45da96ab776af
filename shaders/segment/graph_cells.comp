#version 450
// The uniform grid's cell key of every node (sorted next, so a cell's nodes are one run).
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"
#include "segment/graph_grid.glsl"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Pos { vec4 pos[]; };
layout(std430, binding = 1) writeonly buffer Keys { uint keys[]; };
layout(std430, binding = 2) writeonly buffer Values { uint values[]; };
layout(push_constant) uniform Push { GraphGridPush pc; };

void main() {
    uint i = pg_global_index();
    if (i >= pc.bits.z) return;
    keys[i] = cell_key(cell_of(pos[i].xyz, pc.origin, pc.dims), pc.bits);
    values[i] = i;
}

#version 450
// The nodes' positions (float bits) in sorted cell order, each with its node id in w (as uints:
// an id read as a float could be a denormal a driver flushes): graph_knn then reads
// one vec4 per candidate (on lavapipe every load whose address differs between invocations
// is a loop over the lanes, so loads per candidate set the search's pace).
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Pos { vec4 pos[]; };
layout(std430, binding = 1) readonly buffer Values { uint values[]; };  // node of each sorted key
layout(std430, binding = 2) writeonly buffer Sorted { uvec4 sorted_pos[]; };
layout(push_constant) uniform Push { GraphGridPush pc; };

void main() {
    uint s = pg_global_index();
    if (s >= pc.bits.z) return;
    uint i = values[s];
    sorted_pos[s] = uvec4(floatBitsToUint(pos[i].xyz), i);
}

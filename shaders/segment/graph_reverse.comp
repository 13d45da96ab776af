#version 450
// Each slot of the reverse half (no twin) into the tail of its row j, in whatever order the
// atomics give: graph_rows sorts each row's tail by slot id, so the layout does not depend on it.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Nbr { uint nbr[]; };
layout(std430, binding = 1) readonly buffer Twin { uint twin[]; };
layout(std430, binding = 2) readonly buffer Rows { uint rows[]; };
layout(std430, binding = 3) buffer ReverseCount { uint reverse_count[]; };  // graph_twins' counts
layout(std430, binding = 4) writeonly buffer Columns { uint columns[]; };   // slot ids for now
layout(push_constant) uniform Push { GraphEdgesPush pc; };

void main() {
    uint t = pg_global_index();
    uint n = pc.size.x, k = pc.size.y;
    if (t >= n * k) return;
    uint j = nbr[t];
    if (j == kGraphNone || twin[t] != kGraphNone) return;
    uint left = atomicAdd(reverse_count[j], 0xFFFFFFFFu);  // m, m - 1, ..., 1 for the row's m slots
    columns[rows[j + 1u] - left] = t;
}

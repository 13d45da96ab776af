#version 450
// Each slot of the reverse half (no twin) into the tail of its row j, in whatever order the
// atomics give: graph_rows sorts each row's tail by slot id, so the layout does not depend on it.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"

layout(local_size_x = 256) in;
// Reads through texel buffers: gathered in vector code on CPU drivers (graph_knn.comp).
layout(binding = 0, r32ui) readonly uniform uimageBuffer nbr;
layout(binding = 1, r32ui) readonly uniform uimageBuffer twin;
layout(binding = 2, r32ui) readonly uniform uimageBuffer rows;
layout(std430, binding = 3) buffer ReverseCount { uint reverse_count[]; };  // graph_twins' counts
layout(std430, binding = 4) writeonly buffer Columns { uint columns[]; };   // slot ids for now
layout(push_constant) uniform Push { GraphEdgesPush pc; };

void main() {
    uint t = pg_global_index();
    uint n = pc.size.x, k = pc.size.y;
    if (t >= n * k) return;
    uint j = imageLoad(nbr, int(t)).x;
    if (j == kGraphNone || imageLoad(twin, int(t)).x != kGraphNone) return;
    uint left = atomicAdd(reverse_count[j], 0xFFFFFFFFu);  // m, m - 1, ..., 1 for the row's m slots
    columns[imageLoad(rows, int(j + 1u)).x - left] = t;
}

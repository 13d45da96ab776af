#version 450
// Multigrid, going up: every node adds its aggregate's correction (piecewise-constant
// prolongation), scaled, to its pre-smoothed value, in place.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"

layout(local_size_x = 256) in;
// Reads through texel buffers: gathered in vector code on CPU drivers (walk_apply.comp).
layout(binding = 0, r32ui) readonly uniform uimageBuffer parent;  // kGraphNone: out of the system
layout(binding = 1, rgba32f) readonly uniform imageBuffer coarse_z;
layout(std430, binding = 2) buffer Z { vec4 z[]; };
layout(push_constant) uniform Push { WalkCyclePush pc; };
#ifndef WALK_VECS
#error "WALK_VECS: built per column count (shaders/CMakeLists.txt)"
#endif

void main() {
    uint vecs = WALK_VECS;
    uint i = pg_global_index();
    if (i >= pc.size.x) return;
    uint a = imageLoad(parent, int(i)).x;
    if (a == kGraphNone) return;
    for (uint c = 0u; c < vecs; ++c) z[i * vecs + c] += pc.scale.x * imageLoad(coarse_z, int(a * vecs + c));
}

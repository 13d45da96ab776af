#version 450
// One round of the seeded maximum-spanning-forest relaxation (see ForestPush): every free node
// takes, over its edges, the best (width, node past the weakest edge), recomputed from the
// neighbours alone. Reads one state buffer and writes the other (rounds ping-pong, so a round is
// deterministic); counts the nodes that changed into this round's slot.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/graph_shared.h"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Rows { uint rows[]; };
layout(std430, binding = 1) readonly buffer Columns { uint columns[]; };
layout(std430, binding = 2) readonly buffer Weights { float weights[]; };
layout(std430, binding = 3) readonly buffer Seed { int seed[]; };
layout(std430, binding = 4) readonly buffer In { uvec2 state_in[]; };   // (width bits, node past the weakest edge)
layout(std430, binding = 5) writeonly buffer Out { uvec2 state_out[]; };
layout(std430, binding = 6) buffer Changed { uint changed[]; };
layout(push_constant) uniform Push { ForestPush pc; };

shared uint s_changed;

void main() {
    uint i = pg_global_index();
    uint n = pc.size.x;
    if (gl_LocalInvocationIndex == 0u) s_changed = 0u;
    barrier();
    if (i < n) {
        uvec2 old = state_in[i], best = old;
        if (seed[i] == kWalkFree) {
            best = uvec2(0u);
            for (uint s = rows[i]; s < rows[i + 1u]; ++s) {
                uint j = columns[s];
                uvec2 there = state_in[j];
                float w = weights[s];
                if (there.x == 0u || w <= 0.0) continue;
                // Narrower than the neighbour's path: this edge becomes the weakest, j lies past it.
                uvec2 cand = w < uintBitsToFloat(there.x) ? uvec2(floatBitsToUint(w), j) : there;
                if (cand.x > best.x || (cand.x == best.x && cand.y > best.y)) best = cand;
            }
        }
        state_out[i] = best;
        if (best != old) atomicAdd(s_changed, 1u);
    }
    barrier();
    if (gl_LocalInvocationIndex == 0u && s_changed > 0u) atomicAdd(changed[pc.size.z], s_changed);
}

#version 450
// Rulebook: each neighbour nbr[m, t] >= 0 becomes a pair (m, nbr[m, t]) in tap t's list,
// pairs[t * M + i] for i < counts[t] (counts zeroed beforehand). A workgroup takes 256 rows
// of one tap: it numbers its pairs in shared memory, then reserves their range with a single
// global atomic. The order within a tap is arbitrary, which changes no result: an output row
// appears once per tap, and each row sums its taps in tap order whatever the list order.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/conv_shared.glsl"
layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer NbrBuf { int nbr[]; };
layout(std430, binding = 1) buffer CountBuf { uint counts[]; };
layout(std430, binding = 2) writeonly buffer PairBuf { uvec2 pairs[]; };
layout(push_constant) uniform PushBlock { ConvRulesPush pc; };

shared uint local_count, base;

void main() {
    const uint g = pg_group_index();
    const uint t = g % pc.taps, m = (g / pc.taps) * 256u + gl_LocalInvocationIndex;
    if (gl_LocalInvocationIndex == 0u) local_count = 0u;
    barrier();
    const int j = m < pc.M ? nbr[m * pc.taps + t] : -1;
    uint slot = 0u;
    if (j >= 0) slot = atomicAdd(local_count, 1u);
    barrier();
    if (gl_LocalInvocationIndex == 0u) base = atomicAdd(counts[t], local_count);
    barrier();
    if (j >= 0) pairs[t * pc.M + base + slot] = uvec2(m, uint(j));
}

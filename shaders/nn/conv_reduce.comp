#version 450
// The epilogue of the all-taps rulebook convolution (gemm_lanes.glsl's TAPS; conv_shared.glsl's
// ConvReducePush), four columns per invocation: a slice's rows without that tap's neighbour
// were never written, so the table decides which count, not their contents.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/conv_shared.glsl"
#include "nn/gemm_shared.glsl"
layout(local_size_x = 256) in;
// Reads through texel buffers: gathered in vector code on CPU drivers, where a storage buffer
// load at an address that differs between lanes is a loop over the lanes.
layout(binding = 0, rgba32f) readonly uniform imageBuffer part;  // [taps, M, N]
layout(binding = 1, r32i) readonly uniform iimageBuffer nbr;     // [M, taps]
layout(binding = 2, rgba32f) readonly uniform imageBuffer bias;
layout(std430, binding = 3) writeonly buffer YBuf { vec4 y[]; };
layout(push_constant) uniform PushBlock { ConvReducePush pc; };

void main() {
    const uint i = pg_global_index(), quads = pc.N / 4u;  // N % 8 == 0 on this path
    if (i >= pc.M * quads) return;
    const uint m = i / quads;
    vec4 v = (pc.flags & PG_GEMM_BIAS) != 0u ? imageLoad(bias, int(i % quads)) : vec4(0.0);
    for (uint t = 0u; t < pc.taps; ++t) {
        const vec4 p = imageLoad(part, int(t * pc.M * quads + i));
        v += imageLoad(nbr, int(m * pc.taps + t)).x >= 0 ? p : vec4(0.0);
    }
    y[i] = v;
}

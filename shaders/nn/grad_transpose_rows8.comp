#version 450
// nn/grad_transpose_rows on 8x8 blocks, for K % 8 == 0 (and cin % 8 == 0 when gathered): an
// invocation reads 8 rows of 8 floats and writes 8 columns of 8 floats, each as one u64vec4.
// CPU drivers pay per load instruction per lane, so this moves 8x fewer of them. The output
// has `rows` columns (a multiple of 8); rows at or past M read as 0 (padding for the GEMM).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "common/dispatch.glsl"
#include "nn/grad_shared.glsl"
layout(local_size_x = PG_GRAD_THREADS) in;
layout(std430, binding = 0) readonly buffer XBuf { u64vec4 x8[]; };
layout(std430, binding = 1) readonly buffer NbrBuf { int nbr[]; };
layout(std430, binding = 2) writeonly buffer OutBuf { u64vec4 out8[]; };
layout(push_constant) uniform PushBlock { TransposeRowsPush pc; };

void main() {
    const uint i = pg_global_index();
    const uint kblocks = pc.K / 8u, rblocks = pc.rows / 8u;
    if (i >= kblocks * rblocks) return;
    const uint kb = i / rblocks, rb = i % rblocks;
    const uint t = (kb * 8u) / pc.cin, c8 = ((kb * 8u) % pc.cin) / 8u;  // gathered: tap and column block
    float v[8][8];
    [[unroll]] for (uint r = 0u; r < 8u; ++r) {
        const uint m = pc.m0 + rb * 8u + r;
        const bool live = m < pc.M;
        const uint mc = live ? m : 0u;
        uint src = mc * kblocks + kb;
        bool present = live;
        if (pc.gather != 0u) {
            const int j = nbr[mc * pc.taps + t];
            present = present && j >= 0;
            src = uint(max(j, 0)) * (pc.cin / 8u) + c8;
        }
        const u64vec4 q = x8[src];
        const uvec2 a = unpack32(q.x), b = unpack32(q.y), c = unpack32(q.z), d = unpack32(q.w);
        v[r][0] = present ? uintBitsToFloat(a.x) : 0.0;
        v[r][1] = present ? uintBitsToFloat(a.y) : 0.0;
        v[r][2] = present ? uintBitsToFloat(b.x) : 0.0;
        v[r][3] = present ? uintBitsToFloat(b.y) : 0.0;
        v[r][4] = present ? uintBitsToFloat(c.x) : 0.0;
        v[r][5] = present ? uintBitsToFloat(c.y) : 0.0;
        v[r][6] = present ? uintBitsToFloat(d.x) : 0.0;
        v[r][7] = present ? uintBitsToFloat(d.y) : 0.0;
    }
    [[unroll]] for (uint k = 0u; k < 8u; ++k) {
        out8[(kb * 8u + k) * rblocks + rb] =
            u64vec4(pack64(uvec2(floatBitsToUint(v[0][k]), floatBitsToUint(v[1][k]))),
                    pack64(uvec2(floatBitsToUint(v[2][k]), floatBitsToUint(v[3][k]))),
                    pack64(uvec2(floatBitsToUint(v[4][k]), floatBitsToUint(v[5][k]))),
                    pack64(uvec2(floatBitsToUint(v[6][k]), floatBitsToUint(v[7][k]))));
    }
}

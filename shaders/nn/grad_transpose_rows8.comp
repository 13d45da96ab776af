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
// Reads through texel buffers: on CPU drivers a texel load is gathered in vector code, a storage
// buffer load at an address that differs between lanes is a loop over the lanes.
layout(binding = 0, rgba32f) readonly uniform imageBuffer x4;  // 8 floats: two texels
layout(binding = 1, r32i) readonly uniform iimageBuffer nbr;
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
            const int j = imageLoad(nbr, int(mc * pc.taps + t)).x;
            present = present && j >= 0;
            src = uint(max(j, 0)) * (pc.cin / 8u) + c8;
        }
        const vec4 lo = imageLoad(x4, int(2u * src)), hi = imageLoad(x4, int(2u * src + 1u));
        [[unroll]] for (uint k = 0u; k < 4u; ++k) {
            v[r][k] = present ? lo[k] : 0.0;
            v[r][4u + k] = present ? hi[k] : 0.0;
        }
    }
    [[unroll]] for (uint k = 0u; k < 8u; ++k) {
        out8[(kb * 8u + k) * rblocks + rb] =
            u64vec4(pack64(uvec2(floatBitsToUint(v[0][k]), floatBitsToUint(v[1][k]))),
                    pack64(uvec2(floatBitsToUint(v[2][k]), floatBitsToUint(v[3][k]))),
                    pack64(uvec2(floatBitsToUint(v[4][k]), floatBitsToUint(v[5][k]))),
                    pack64(uvec2(floatBitsToUint(v[6][k]), floatBitsToUint(v[7][k]))));
    }
}

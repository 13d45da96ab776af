#version 450
// nn/grad_transpose_rows for any width: an invocation takes 8 rows of one tap's cin columns
// (dense: the whole row) and writes each column's 8 values as one u64vec4. The neighbour of
// each row is read once per tap, not once per value, and a store moves 8 values: on CPU
// drivers, where every load and store is a loop over the lanes, that halves the work of the
// stem's weight gradient (cin not a multiple of 8, so nn/grad_transpose_rows8 cannot take it).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "common/dispatch.glsl"
#include "nn/grad_shared.glsl"
#include "nn/pack8.glsl"
layout(local_size_x = PG_GRAD_THREADS) in;
layout(std430, binding = 0) readonly buffer XBuf { float x[]; };
layout(std430, binding = 1) readonly buffer NbrBuf { int nbr[]; };
layout(std430, binding = 2) writeonly buffer OutBuf { u64vec4 out8[]; };
layout(push_constant) uniform PushBlock { TransposeRowsPush pc; };

void main() {
    const uint i = pg_global_index();
    const uint rblocks = pc.rows / 8u;  // pc.rows: the padded window, a multiple of 8
    if (i >= pc.taps * rblocks) return;
    const uint t = i / rblocks, rb = i % rblocks;
    uint base[8];
    bool present[8];
    [[unroll]] for (uint r = 0u; r < 8u; ++r) {
        const uint m = pc.m0 + rb * 8u + r;
        const uint mc = min(m, pc.M - 1u);
        int j = int(mc);
        if (pc.gather != 0u) j = nbr[mc * pc.taps + t];
        present[r] = m < pc.M && j >= 0;
        base[r] = pc.gather != 0u ? uint(max(j, 0)) * pc.cin : mc * pc.K;
    }
    for (uint c = 0u; c < pc.cin; ++c) {
        float v[8];
        [[unroll]] for (uint r = 0u; r < 8u; ++r) v[r] = present[r] ? x[base[r] + c] : 0.0;
        out8[(t * pc.cin + c) * rblocks + rb] = pack8(vec4(v[0], v[1], v[2], v[3]), vec4(v[4], v[5], v[6], v[7]));
    }
}

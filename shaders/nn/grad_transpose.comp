#version 450
// Per-tap transpose of a conv weight w [rows, taps*cin] into [cin, taps*rows]:
// out[c, t*rows + o] = w[o, t'*cin + c], t' = taps-1-t when flipped (the mirrored offsets of the
// submanifold map, nn/train/grad_ops.h) or t. taps = 1 is the plain matrix transpose.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/grad_shared.glsl"
layout(local_size_x = PG_GRAD_THREADS) in;
layout(std430, binding = 0) readonly buffer WBuf { float w[]; };
layout(std430, binding = 1) writeonly buffer OutBuf { float outv[]; };
layout(push_constant) uniform PushBlock { TransposePush pc; };

void main() {
    const uint i = pg_global_index();
    const uint width = pc.taps * pc.rows;  // of the output
    if (i >= pc.cin * width) return;
    const uint c = i / width, rest = i % width;
    const uint t = rest / pc.rows, o = rest % pc.rows;
    const uint ts = pc.flip != 0u ? pc.taps - 1u - t : t;
    outv[i] = w[o * pc.taps * pc.cin + ts * pc.cin + c];
}

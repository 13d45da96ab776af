#version 450
// Radix sort: copies the first `count` keys and values back from the scratch buffers after
// an odd number of passes (a transfer copy would need the count on the host).
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "sort/sort_config.h"
layout(local_size_x = PG_SORT_THREADS) in;
layout(std430, binding = 0) readonly buffer Params { uint params[]; };
layout(std430, binding = 1) readonly buffer SrcKeys { uint src_keys[]; };
layout(std430, binding = 2) readonly buffer SrcValues { uint src_values[]; };
layout(std430, binding = 3) writeonly buffer DstKeys { uint dst_keys[]; };
layout(std430, binding = 4) writeonly buffer DstValues { uint dst_values[]; };
layout(push_constant) uniform PushBlock { RadixCopyPush pc; };

void main() {
    uint n = params[PG_SORT_PARAM_COUNT];
    uint begin = pg_group_index() * PG_SORT_BLOCK;
    if (begin >= n) return;
    for (uint i = 0u; i < PG_SORT_ITEMS; ++i) {
        uint e = begin + i * PG_SORT_THREADS + gl_LocalInvocationIndex;
        if (e < n) {
            for (uint w = 0u; w < pc.key_words; ++w) dst_keys[e * pc.key_words + w] = src_keys[e * pc.key_words + w];
            dst_values[e] = src_values[e];
        }
    }
}

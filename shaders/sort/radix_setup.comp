#version 450
// Radix sort, indirect path: clamps the GPU-written count to the scratch capacity and turns
// it into the parameter buffer (indirect arguments of one group per block, then the count).
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "sort/sort_config.h"
layout(local_size_x = 1) in;
layout(std430, binding = 0) readonly buffer Count { uint counts[]; };
layout(std430, binding = 1) writeonly buffer Params { uint params[]; };
layout(push_constant) uniform PushBlock { RadixSetupPush pc; };

void main() {
    uint n = min(counts[pc.count_index], pc.capacity);
    uint groups = n / PG_SORT_BLOCK + (n % PG_SORT_BLOCK != 0u ? 1u : 0u);
    PG_WRITE_DISPATCH(params, PG_SORT_PARAM_ARGS, groups, pc.limit);
    params[PG_SORT_PARAM_COUNT] = n;
}

#version 450
// Fills n uints with a value: the smallest kernel, used by the Vulkan core tests.
#extension GL_GOOGLE_include_directive : require
#include "common/common_shared.h"
#include "common/dispatch.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) buffer Data { uint data[]; };
layout(push_constant) uniform Push { FillPush pc; };
void main() {
    uint i = pg_global_index();
    if (i < pc.n) data[i] = pc.value + i;
}

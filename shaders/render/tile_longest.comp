#version 450
// The longest tile list of the frame into counts[1] (zeroed before): how many windows the
// passes that walk the lists need.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "render/render_shared.h"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Frame { FrameParams frame; };
layout(std430, binding = 1) readonly buffer Ranges { uvec2 ranges[]; };
layout(std430, binding = 2) buffer Counts { uint counts[]; };

void main() {
    uint t = pg_global_index();
    if (t >= frame.size.z * frame.size.w) return;
    uvec2 r = ranges[t];
    if (r.y > r.x) atomicMax(counts[1], r.y - r.x);
}

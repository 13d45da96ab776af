#version 450
// A streamed slab's style labels: the scene's label of each slab Gaussian, by the slab's ids.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "render/render_shared.h"

layout(local_size_x = 256) in;
layout(push_constant) uniform Push { GatherPush push; };
layout(std430, binding = 0) readonly buffer SlabIds { uint slab_ids[]; };
layout(std430, binding = 1) readonly buffer SceneLabels { int scene_labels[]; };
layout(std430, binding = 2) writeonly buffer SlabLabels { int slab_labels[]; };

void main() {
    uint k = pg_global_index();
    if (k < push.count.x) slab_labels[k] = scene_labels[slab_ids[k]];
}

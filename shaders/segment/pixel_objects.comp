#version 450
// Which object each pixel of a frame shows, for picking objects by pointing at them: the label
// of the Gaussian at which the pixel's opacity reached tau (the renderer's aux.z), 0 where no
// Gaussian did.
#extension GL_GOOGLE_include_directive : require
#include "segment/picture_shared.h"

layout(local_size_x = kPictureSide, local_size_y = kPictureSide) in;
layout(std430, binding = 0) readonly buffer Aux { uvec4 aux[]; };   // depth, tau-depth, tau id, contributors
layout(std430, binding = 1) readonly buffer Labels { int labels[]; };  // object id per Gaussian
layout(std430, binding = 2) writeonly buffer Objects { int objects[]; };
layout(push_constant) uniform Push { PixelObjectsPush pc; };

void main() {
    uint x = gl_GlobalInvocationID.x, y = gl_GlobalInvocationID.y;
    if (x >= pc.width || y >= pc.height) return;
    uint p = y * pc.width + x;
    uint g = aux[p].z;  // kNoGaussian where tau was never reached
    objects[p] = g < uint(labels.length()) ? labels[g] : 0;
}

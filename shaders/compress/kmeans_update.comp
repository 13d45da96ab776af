#version 450
// k-means update: each centroid coordinate becomes the mean of its members' coordinates, summed
// in sorted (point index) order with Kahan compensation, so every run gives the same bytes and
// the mean is as good as a double sum. An empty cluster keeps its centroid.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Points { float points[]; };
layout(std430, binding = 1) readonly buffer Members { uint members[]; };  // point indices by label
layout(std430, binding = 2) readonly buffer Start { uint start[]; };
layout(std430, binding = 3) readonly buffer End { uint end_[]; };
layout(std430, binding = 4) buffer Centroids { float centroids[]; };
layout(push_constant) uniform Push { uint k, dims; } pc;

void main() {
    uint t = pg_global_index();
    if (t >= pc.k * pc.dims) return;
    uint c = t / pc.dims, d = t % pc.dims;
    uint s = start[c], e = end_[c];
    if (e <= s) return;
    precise float sum = 0.0, carry = 0.0;
    for (uint j = s; j < e; ++j) {
        precise float y = points[members[j] * pc.dims + d] - carry;
        precise float next = sum + y;
        carry = (next - sum) - y;
        sum = next;
    }
    centroids[t] = sum / float(e - s);
}

#version 450
// k-means assignment: each point's nearest centroid by squared distance, ties to the lower
// index. Centroids pass through shared memory a tile at a time, so a workgroup reads each once.
// Points come in windows (`first` .. `first + n`) so a scene of any size stays within one binding.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Points { float points[]; };
layout(std430, binding = 1) readonly buffer Centroids { float centroids[]; };
layout(std430, binding = 2) writeonly buffer Labels { uint labels[]; };
layout(push_constant) uniform Push {
    uint n;     // points in this window
    uint k;     // centroids
    uint dims;  // floats per point, at most kMaxDims
} pc;

const uint kMaxDims = 48u;
const uint kTile = 64u;
shared float tile[kTile * kMaxDims];

void main() {
    uint i = pg_global_index();
    bool live = i < pc.n;
    float p[kMaxDims];
    for (uint d = 0u; d < pc.dims; ++d) p[d] = live ? points[i * pc.dims + d] : 0.0;
    float best = 1.0 / 0.0;
    uint label = 0u;
    for (uint base = 0u; base < pc.k; base += kTile) {
        uint count = min(kTile, pc.k - base);
        barrier();
        for (uint t = gl_LocalInvocationIndex; t < count * pc.dims; t += gl_WorkGroupSize.x)
            tile[t] = centroids[base * pc.dims + t];
        barrier();
        if (!live) continue;
        for (uint c = 0u; c < count; ++c) {
            float d2 = 0.0;
            for (uint d = 0u; d < pc.dims; ++d) {
                float e = p[d] - tile[c * pc.dims + d];
                d2 += e * e;
            }
            if (d2 < best) {
                best = d2;
                label = base + c;
            }
        }
    }
    if (live) labels[i] = label;
}

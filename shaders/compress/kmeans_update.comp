#version 450
// k-means update, last: each centroid coordinate becomes its cluster's sum over all windows
// divided by the member count. An empty cluster keeps its centroid.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "compress/kmeans_shared.h"

layout(local_size_x = PG_KMEANS_THREADS) in;
layout(std430, binding = 0) readonly buffer Sum { float sum[]; };
layout(std430, binding = 1) readonly buffer Count { uint count[]; };
layout(std430, binding = 2) buffer Centroids { float centroids[]; };
layout(push_constant) uniform Push { KmeansClusterPush pc; };

void main() {
    const uint t = pg_global_index();
    if (t >= pc.k * pc.dims) return;
    const uint members = count[t / pc.dims];
    if (members > 0u) centroids[t] = sum[t] / float(members);
}

#version 450
// Connected components, step 1 of 3: union-find inside one 16x16 tile in shared memory.
// Writes parent = the global index of the pixel's tile-local root (the smallest index of its
// tile-local component; the tile's row-major order is the image's), parent = self for
// pixels outside every component, and optionally each tile-local root's pixel count.
#extension GL_GOOGLE_include_directive : require
#include "segment/refine_shared.h"

layout(local_size_x = PG_CC_TILE, local_size_y = PG_CC_TILE) in;
layout(std430, binding = 0) readonly buffer Labels { uint labels[]; };
layout(std430, binding = 1) writeonly buffer Parent { uint g_parent[]; };
layout(std430, binding = 2) writeonly buffer Sizes { uint sizes[]; };
layout(push_constant) uniform Push { CcPush pc; };

shared uint parent[PG_CC_THREADS];  // tile-local union-find, by local index
shared uint s_label[PG_CC_THREADS];
shared uint s_count[PG_CC_THREADS];
#include "segment/refine_union_find.glsl"

void main() {
    const uint lid = gl_LocalInvocationIndex;
    const uint lx = gl_LocalInvocationID.x, ly = gl_LocalInvocationID.y;
    const uint x = gl_WorkGroupID.x * PG_CC_TILE + lx, y = gl_WorkGroupID.y * PG_CC_TILE + ly;
    const bool inside = x < pc.width && y < pc.height;
    // Tile pixels past the image's right or bottom edge exist only locally and join nothing.
    const uint w_in = min(PG_CC_TILE, pc.width - gl_WorkGroupID.x * PG_CC_TILE);
    const uint label = inside ? labels[y * pc.width + x] : 0u;
    const bool member = inside && cc_member(pc.mode, label);
    parent[lid] = lid;
    s_label[lid] = label;
    s_count[lid] = 0u;
    barrier();
    if (member) {
        if (lx > 0u && cc_joined(pc.mode, label, s_label[lid - 1u])) uf_union(lid, lid - 1u);
        if (ly > 0u && cc_joined(pc.mode, label, s_label[lid - PG_CC_TILE])) uf_union(lid, lid - PG_CC_TILE);
        if (pc.mode == PG_CC_LABEL_8 && ly > 0u) {
            if (lx > 0u && cc_joined(pc.mode, label, s_label[lid - PG_CC_TILE - 1u]))
                uf_union(lid, lid - PG_CC_TILE - 1u);
            if (lx + 1u < w_in && cc_joined(pc.mode, label, s_label[lid - PG_CC_TILE + 1u]))
                uf_union(lid, lid - PG_CC_TILE + 1u);
        }
    }
    barrier();
    const uint root = member ? uf_find(lid) : lid;
    if (member) atomicAdd(s_count[root], 1u);
    barrier();
    if (!inside) return;
    const uint g = y * pc.width + x;
    const uint groot = (gl_WorkGroupID.y * PG_CC_TILE + root / PG_CC_TILE) * pc.width +
                       gl_WorkGroupID.x * PG_CC_TILE + root % PG_CC_TILE;
    g_parent[g] = groot;
    if (pc.write_sizes != 0u) sizes[g] = member && root == lid ? s_count[lid] : 0u;
}

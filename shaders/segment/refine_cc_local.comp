#version 450
// Connected components, step 1 of 3: union-find inside one 32x32 tile in shared memory, four
// pixels per invocation. Writes parent = the global index of the pixel's tile-local root (the
// smallest index of its tile-local component: the tile's row-major order is the image's),
// parent = self for pixels outside every component, and optionally each tile-local root's
// pixel count into `sizes` (which must start at 0; nothing else is written there).
// Per-pixel values live in shared arrays: the loops over an invocation's pixels hold loops
// and need not be unrolled.
#extension GL_GOOGLE_include_directive : require
#include "segment/refine_shared.h"

layout(local_size_x = PG_CC_THREADS) in;
layout(std430, binding = 0) readonly buffer Labels { uint labels[]; };
layout(std430, binding = 1) writeonly buffer Parent { uint g_parent[]; };
layout(std430, binding = 2) writeonly buffer Sizes { uint sizes[]; };
layout(push_constant) uniform Push { CcPush pc; };

#define CELLS (PG_CC_TILE * PG_CC_TILE)
#define OUTSIDE 0xFFFFFFFFu  // s_root of a tile pixel past the image
shared uint parent[CELLS];   // tile-local union-find, by local index
shared uint s_label[CELLS];
shared uint s_root[CELLS];   // the pixel's root; the pixel itself outside every component
shared uint s_count[CELLS];
#include "segment/refine_union_find.glsl"

void main() {
    const uint lid = gl_LocalInvocationIndex;
    const uint x0 = gl_WorkGroupID.x * PG_CC_TILE, y0 = gl_WorkGroupID.y * PG_CC_TILE;
    // Tile pixels past the image's right or bottom edge exist only here and join nothing.
    const uint w_in = min(PG_CC_TILE, pc.width - x0), h_in = min(PG_CC_TILE, pc.height - y0);
    for (uint k = 0u; k < PG_CC_PIXELS; ++k) {
        const uint i = lid + k * PG_CC_THREADS, lx = i % PG_CC_TILE, ly = i / PG_CC_TILE;
        const bool inside = lx < w_in && ly < h_in;
        const uint l = inside ? labels[(y0 + ly) * pc.width + x0 + lx] : 0u;
        parent[i] = i;
        s_label[i] = l;
        s_root[i] = inside && cc_member(pc.mode, l) ? i : OUTSIDE;  // members: i for now
        s_count[i] = 0u;
    }
    barrier();
    for (uint k = 0u; k < PG_CC_PIXELS; ++k) {
        const uint i = lid + k * PG_CC_THREADS, lx = i % PG_CC_TILE, ly = i / PG_CC_TILE;
        if (s_root[i] == OUTSIDE) continue;
        const uint l = s_label[i];
        if (lx > 0u && cc_joined(pc.mode, l, s_label[i - 1u])) uf_union(i, i - 1u);
        if (ly > 0u && cc_joined(pc.mode, l, s_label[i - PG_CC_TILE])) uf_union(i, i - PG_CC_TILE);
        if (pc.mode == PG_CC_LABEL_8 && ly > 0u) {
            if (lx > 0u && cc_joined(pc.mode, l, s_label[i - PG_CC_TILE - 1u])) uf_union(i, i - PG_CC_TILE - 1u);
            if (lx + 1u < w_in && cc_joined(pc.mode, l, s_label[i - PG_CC_TILE + 1u])) uf_union(i, i - PG_CC_TILE + 1u);
        }
    }
    barrier();
    for (uint k = 0u; k < PG_CC_PIXELS; ++k) {
        const uint i = lid + k * PG_CC_THREADS;
        if (s_root[i] == OUTSIDE) continue;
        const uint root = uf_find(i);
        s_root[i] = root;
        if (pc.write_sizes != 0u) atomicAdd(s_count[root], 1u);
    }
    barrier();
    for (uint k = 0u; k < PG_CC_PIXELS; ++k) {
        const uint i = lid + k * PG_CC_THREADS, lx = i % PG_CC_TILE, ly = i / PG_CC_TILE;
        if (lx >= w_in || ly >= h_in) continue;
        const uint member_root = s_root[i];
        const uint r = member_root == OUTSIDE ? i : member_root;  // non-members: their own root
        const uint g = (y0 + ly) * pc.width + x0 + lx;
        g_parent[g] = (y0 + r / PG_CC_TILE) * pc.width + x0 + r % PG_CC_TILE;
        if (pc.write_sizes != 0u && member_root == i) sizes[g] = s_count[i];
    }
}

#version 450
// Connected components, step 1 of 3: union-find inside one 32x32 tile in shared memory, four
// pixels per invocation. Writes parent = the global index of the pixel's tile-local root (the
// smallest index of its tile-local component: the tile's row-major order is the image's),
// parent = self for pixels outside every component, and optionally each tile-local root's
// pixel count into `sizes` (which must start at 0; nothing else is written there).
// Rows are first cut into runs, serially; the union-find then only joins runs with the runs
// above them, where they first meet.
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
        s_label[i] = l;
        s_root[i] = inside && cc_member(pc.mode, l) ? i : OUTSIDE;  // members: i for now
        s_count[i] = 0u;
    }
    barrier();
    // Runs along each row, one invocation per row: every pixel's parent is its run's first
    // pixel. Walking the row serially keeps the union-find trees flat (lavapipe runs a loop
    // for as long as its slowest lane, so long chains cost every pixel).
    if (lid < PG_CC_TILE) {
        const uint row = lid * PG_CC_TILE;
        uint head = row;
        for (uint x = 0u; x < PG_CC_TILE; ++x) {
            const uint i = row + x;
            const bool member = s_root[i] != OUTSIDE;
            if (!member || x == 0u || !cc_joined(pc.mode, s_label[i], s_label[i - 1u])) head = i;
            parent[i] = member ? head : i;
        }
    }
    barrier();
    // Joins with the row above, only where a run first meets a run there (the rest of the
    // contact is reached along the two runs): 8-connected, a pixel after a joined W pixel only
    // needs NE, and only when N is not joined; 4-connected, N unless W and NW both joined.
    for (uint k = 0u; k < PG_CC_PIXELS; ++k) {
        const uint i = lid + k * PG_CC_THREADS, lx = i % PG_CC_TILE, ly = i / PG_CC_TILE;
        if (s_root[i] == OUTSIDE || ly == 0u) continue;
        const uint l = s_label[i];
        const bool w_joined = lx > 0u && cc_joined(pc.mode, l, s_label[i - 1u]);
        const bool n_joined = cc_joined(pc.mode, l, s_label[i - PG_CC_TILE]);
        const bool nw_joined = lx > 0u && cc_joined(pc.mode, l, s_label[i - PG_CC_TILE - 1u]);
        if (pc.mode == PG_CC_LABEL_8) {
            const bool ne_joined = lx + 1u < w_in && cc_joined(pc.mode, l, s_label[i - PG_CC_TILE + 1u]);
            if (!w_joined) {
                if (n_joined) {
                    uf_union(i, i - PG_CC_TILE);
                } else {
                    if (nw_joined) uf_union(i, i - PG_CC_TILE - 1u);
                    if (ne_joined) uf_union(i, i - PG_CC_TILE + 1u);
                }
            } else if (!n_joined && ne_joined) {
                uf_union(i, i - PG_CC_TILE + 1u);
            }
        } else if (n_joined && !(w_joined && nw_joined)) {
            uf_union(i, i - PG_CC_TILE);
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

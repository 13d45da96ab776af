#version 450
// One closing radius (definition in engine/segment/mask_refine.h), one workgroup per output
// tile of side T = 64 - 4r, for radii up to (64 - PG_CLOSE_MIN_TILE) / 4.
//
// The region (tile + 2r apron, side E <= 64) is kept as bit rows: one uvec2 per region row
// and instance, bit c = region column c (.x: 0-31, .y: 32-63). The instances within r of the
// tile come in ascending batches of up to 16 (so any number of them works, and the first
// batch that covers a pixel holds its smallest k); per batch and instance, two shared arrays
// take turns:
//   x: the instance's pixels                   rows [0, E)
//   y: row dilation (shifts)                   rows [0, E)
//   x: column dilation, all ones outside the image (the erosion's border)   rows [r, E - r)
//   y: row erosion                             rows [r, E - r)
//   x: column erosion                          rows [2r, E - 2r)
// Region columns past the image are 0 in the pixels, so they dilate nothing. Shifts bring in
// zeros at the region's edges; that only reaches columns the tile never reads.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/refine_shared.h"

layout(local_size_x = PG_CLOSE_THREADS) in;
layout(std430, binding = 0) readonly buffer Src { uint src[]; };
layout(std430, binding = 1) buffer Dst { uint dst[]; };
layout(push_constant) uniform Push { ClosePush pc; };

#define PG_CLOSE_LIST PG_CLOSE_BATCH
#include "segment/refine_close_tile.glsl"

// Bit rows: [instance * PG_CLOSE_REGION + row] as uvec2, stored as two uints for atomicOr.
shared uint s_x[PG_CLOSE_BATCH * PG_CLOSE_REGION * 2];
shared uint s_y[PG_CLOSE_BATCH * PG_CLOSE_REGION * 2];
#define GET(a, i) uvec2(a[2u * (i)], a[2u * (i) + 1u])
#define PUT(a, i, v)              \
    {                             \
        uvec2 v_ = (v);           \
        a[2u * (i)] = v_.x;       \
        a[2u * (i) + 1u] = v_.y;  \
    }

// Bit c takes bit c + d (d in 1..31).
uvec2 take_right(uvec2 v, uint d) { return uvec2((v.x >> d) | (v.y << (32u - d)), v.y >> d); }
// Bit c takes bit c - d.
uvec2 take_left(uvec2 v, uint d) { return uvec2(v.x << d, (v.y << d) | (v.x >> (32u - d))); }
// Bits 0..n-1 set, n clamped to 0..64.
uvec2 low_bits(int n) {
    const uint lo = n >= 32 ? 0xFFFFFFFFu : (n <= 0 ? 0u : (1u << uint(n)) - 1u);
    const uint hi = n >= 64 ? 0xFFFFFFFFu : (n <= 32 ? 0u : (1u << uint(n - 32)) - 1u);
    return uvec2(lo, hi);
}

void main() {
    const uint tile = pc.tile_base + pg_group_index();
    if (tile >= pc.tile_count) return;  // the folded grid's spare groups: whole workgroups
    const uint lid = gl_LocalInvocationIndex;
    const int w = int(pc.width), h = int(pc.height), r = int(pc.radius), T = int(pc.tile);
    const int x0 = int(tile % pc.tiles_x) * T, y0 = int(tile / pc.tiles_x) * T;
    const int E = T + 4 * r, rx = x0 - 2 * r, ry = y0 - 2 * r;  // region side and origin
    const uint ur = uint(r), uE = uint(E);
    // Region columns outside the image.
    const uvec2 outside = low_bits(-rx) | ~low_bits(w - rx);

    if (!close_copy_tile(x0, y0, T)) return;  // uniform
    uint prev = 0u;
    for (;;) {
        const uint count = close_next_batch(prev, PG_CLOSE_BATCH, x0, y0, T);
        if (count == 0u) break;
        const uint rows = count * PG_CLOSE_REGION;  // bit rows of the batch, all instances
        for (uint i = lid; i < rows; i += PG_CLOSE_THREADS) PUT(s_x, i, uvec2(0u));
        barrier();
        PG_CLOSE_FOR_2D(c, row, E, E) {
            const int x = rx + c, y = ry + row;
            if (x < 0 || y < 0 || x >= w || y >= h) continue;
            const int j = close_batch_index(src[y * w + x], count);
            if (j >= 0) atomicOr(s_x[2 * (j * PG_CLOSE_REGION + row) + c / 32], 1u << uint(c % 32));
        }
        barrier();
        // Each step below runs over (instance, row) pairs: i = instance * PG_CLOSE_REGION + row.
        for (uint i = lid; i < rows; i += PG_CLOSE_THREADS) {
            if (i % PG_CLOSE_REGION >= uE) continue;
            const uvec2 v = GET(s_x, i);
            uvec2 a = v;
            for (uint d = 1u; d <= ur; ++d) a |= take_right(v, d) | take_left(v, d);
            PUT(s_y, i, a);
        }
        barrier();
        for (uint i = lid; i < rows; i += PG_CLOSE_THREADS) {
            const uint row = i % PG_CLOSE_REGION;
            if (row < ur || row >= uE - ur) continue;
            uvec2 a = uvec2(0xFFFFFFFFu);  // a row outside the image: every pixel set
            const int y = ry + int(row);
            if (y >= 0 && y < h) {
                a = outside;
                for (uint d = 0u; d <= 2u * ur; ++d) a |= GET(s_y, i - ur + d);
            }
            PUT(s_x, i, a);
        }
        barrier();
        for (uint i = lid; i < rows; i += PG_CLOSE_THREADS) {
            const uint row = i % PG_CLOSE_REGION;
            if (row < ur || row >= uE - ur) continue;
            const uvec2 v = GET(s_x, i);
            uvec2 a = v;
            for (uint d = 1u; d <= ur; ++d) a &= take_right(v, d) & take_left(v, d);
            PUT(s_y, i, a);
        }
        barrier();
        for (uint i = lid; i < rows; i += PG_CLOSE_THREADS) {
            const uint row = i % PG_CLOSE_REGION;
            if (row < 2u * ur || row >= uE - 2u * ur) continue;
            uvec2 a = uvec2(0xFFFFFFFFu);
            for (uint d = 0u; d <= 2u * ur; ++d) a &= GET(s_y, i - ur + d);
            PUT(s_x, i, a);
        }
        barrier();
        // Unassigned 0-pixels take the first (smallest) instance whose closing holds them.
        PG_CLOSE_FOR_2D(lx, ly, T, T) {
            const int x = x0 + lx, y = y0 + ly;
            if (x >= w || y >= h) continue;
            if (src[y * w + x] != 0u || dst[y * w + x] != 0u) continue;  // dst: this invocation's own write
            const int c = lx + 2 * r, row = ly + 2 * r;
            for (uint j = 0u; j < count; ++j)
                if ((s_x[2 * (int(j) * PG_CLOSE_REGION + row) + c / 32] & (1u << uint(c % 32))) != 0u) {
                    dst[y * w + x] = s_list[j];
                    break;
                }
        }
        if (count < PG_CLOSE_BATCH) break;  // uniform: no more instances
        barrier();  // the arrays and s_list are reused by the next batch
    }
}

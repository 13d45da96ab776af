#version 450
// One closing radius (definition in engine/segment/mask_refine.h), one workgroup per output
// tile of side T = 64 - 4r, for radii up to (64 - PG_CLOSE_MIN_TILE) / 4. dst must hold a copy
// of src: only the pixels that change are written.
//
// The tile plus a 2r apron (the region, side E = T + 4r <= 64) sits in a 64 x 64 grid of
// which every invocation owns 16 cells (column lid % 64, rows lid / 64 + 4k), held in
// private arrays: loops over pixels have constant trip counts. The instances within r of the
// tile (only they can claim its pixels) are collected in one pass while there are at most 32
// (a shared hash set, then ranked), else chosen smallest first, one per barrier. They are
// taken in ascending batches of up to 16, so the first batch that covers a pixel holds its
// smallest k. A batch lives in bit rows: a uvec2 per instance and region row, bit c = region
// column c (.x: 0-31, .y: 32-63), in two shared arrays that take turns:
//   x: the instances' pixels                                   rows [0, E)
//   y: row dilation (shifts)                                   rows [0, E)
//   x: column dilation (all ones off the image: the erosion's border), then row erosion
//                                                              rows [r, E - r)
//   y: column erosion, and which rows any instance covers      rows [2r, E - 2r)
// Region columns past the image are 0 in the pixels, so they dilate nothing; shifts bring in
// zeros at the grid's edges, which only reaches columns the tile never reads. Barriers: 3 per
// tile, 6 per batch.
//
// lavapipe ends a shader's loops after 65535 iterations in all (one counter for every loop
// of the shader). What still iterates here is bounded: the hash probes (at most 16 x 64, once
// per tile), the batch and choice loops and the column steps' window loops (at most
// 18 + 8 (2r + 1) per batch of 16 of the <= (T + 2r)^2 instances), the final search (16 per
// pixel per tile): under that for any image.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/refine_shared.h"

layout(local_size_x = PG_CLOSE_THREADS) in;
layout(std430, binding = 0) readonly buffer Src { uint src[]; };
layout(std430, binding = 1) writeonly buffer Dst { uint dst[]; };
layout(push_constant) uniform Push { ClosePush pc; };

#define GRID PG_CLOSE_REGION                              // 64
#define CELLS (GRID * GRID / PG_CLOSE_THREADS)            // 16 per invocation
#define TASKS (PG_CLOSE_BATCH * GRID / PG_CLOSE_THREADS)  // 4 (instance, row) pairs per invocation
#define SET_SLOTS 64
#define SET_MAX 32

// Bit rows: [instance * GRID + row] as uvec2, stored as two uints (for atomicOr).
shared uint s_x[PG_CLOSE_BATCH * GRID * 2];
shared uint s_y[PG_CLOSE_BATCH * GRID * 2];
shared uint s_any[GRID * 2];         // per region row: pixels some instance of the batch covers
shared uint s_list[PG_CLOSE_BATCH];  // the batch's instances, ascending
// The instances within r of the tile while there are at most SET_MAX: a hash set (it stops
// growing at SET_SLOTS), then ascending.
shared uint s_set[SET_SLOTS];
shared uint s_set_count;
shared uint s_sorted[SET_MAX];
// Choosing one by one rotates over three slots, so one barrier per choice does.
shared uint s_next[3];
shared uint s_found[3];
shared uint s_has_zero;

uvec2 x_row(uint i) { return uvec2(s_x[2u * i], s_x[2u * i + 1u]); }
uvec2 y_row(uint i) { return uvec2(s_y[2u * i], s_y[2u * i + 1u]); }
// Bit c takes bit c + d (d in 1..31).
uvec2 take_right(uvec2 v, uint d) { return uvec2((v.x >> d) | (v.y << (32u - d)), v.y >> d); }
// Bit c takes bit c - d.
uvec2 take_left(uvec2 v, uint d) { return uvec2(v.x << d, (v.y << d) | (v.x >> (32u - d))); }
// Along the row, the window [-r, r] as a sum of {-s, 0, s}: s = 1, 2, 4, then the rest (each s
// at most one more than the reach so far, so no offset is missed).
uvec2 dilate_row(uvec2 a, uint r) {
    uint reach = 0u;
    for (int step = 0; step < 4; ++step)
        if (reach < r) {
            const uint s = min(reach + 1u, r - reach);
            a |= take_right(a, s) | take_left(a, s);
            reach += s;
        }
    return a;
}
uvec2 erode_row(uvec2 a, uint r) {
    uint reach = 0u;
    for (int step = 0; step < 4; ++step)
        if (reach < r) {
            const uint s = min(reach + 1u, r - reach);
            a &= take_right(a, s) & take_left(a, s);
            reach += s;
        }
    return a;
}
// Bits 0..n-1 set, n clamped to 0..64.
uvec2 low_bits(int n) {
    const uint lo = n >= 32 ? 0xFFFFFFFFu : (n <= 0 ? 0u : (1u << uint(n)) - 1u);
    const uint hi = n >= 64 ? 0xFFFFFFFFu : (n <= 32 ? 0u : (1u << uint(n - 32)) - 1u);
    return uvec2(lo, hi);
}
uint set_hash(uint x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    return x;
}
// Index of `label` in s_list[0..count), or -1: a binary search with a fixed trip count.
int batch_index(uint label, uint count) {
    if (label == 0u || label < s_list[0] || label > s_list[count - 1u]) return -1;
    uint lo = 0u;
    for (uint step = PG_CLOSE_BATCH / 2u; step > 0u; step >>= 1u)
        if (lo + step < count && s_list[lo + step] <= label) lo += step;
    return s_list[lo] == label ? int(lo) : -1;
}

void main() {
    const uint tile = pc.tile_base + pg_group_index();
    if (tile >= pc.tile_count) return;  // the folded grid's spare groups: whole workgroups
    const uint lid = gl_LocalInvocationIndex;
    const int w = int(pc.width), h = int(pc.height), r = int(pc.radius), T = int(pc.tile);
    const int x0 = int(tile % pc.tiles_x) * T, y0 = int(tile / pc.tiles_x) * T;
    const int E = T + 4 * r, rx = x0 - 2 * r, ry = y0 - 2 * r;  // region side and origin
    const uint ur = uint(r), uE = uint(E);
    const uvec2 outside = low_bits(-rx) | ~low_bits(w - rx);  // region columns off the image
    const int col = int(lid % GRID), row0 = int(lid / GRID);  // this invocation's grid cells

    // The region's labels (0 off the image) and the tile's output so far.
    uint label[CELLS], result[CELLS];
    bool any_zero = false;
    for (int k = 0; k < CELLS; ++k) {
        const int row = row0 + 4 * k, x = rx + col, y = ry + row;
        label[k] = col < E && row < E && x >= 0 && y >= 0 && x < w && y < h ? src[y * w + x] : 0u;
        result[k] = label[k];
        const bool in_tile = col >= 2 * r && col < 2 * r + T && row >= 2 * r && row < 2 * r + T;
        if (in_tile && x < w && y < h && label[k] == 0u) any_zero = true;
    }
    if (lid < SET_SLOTS) s_set[lid] = 0u;
    if (lid == 0u) {
        s_set_count = 0u;
        s_has_zero = 0u;
        s_next[0] = 0xFFFFFFFFu;
        s_found[0] = 0u;
        s_next[1] = 0xFFFFFFFFu;
        s_found[1] = 0u;
    }
    barrier();
    if (any_zero) atomicOr(s_has_zero, 1u);
    // Collect the instances within r of the tile; a run of one label down this invocation's
    // column is offered once.
    uint offered = 0u;
    for (int k = 0; k < CELLS; ++k) {
        const int row = row0 + 4 * k;
        const bool in_window = col >= r && col < E - r && row >= r && row < E - r;
        const uint l = label[k];
        if (!in_window || l == 0u || l == offered) continue;
        offered = l;
        uint slot = set_hash(l) % SET_SLOTS;
        for (uint probe = 0u; probe < SET_SLOTS; ++probe) {
            uint key = s_set[slot];
            if (key == 0u) {
                key = atomicCompSwap(s_set[slot], 0u, l);
                if (key == 0u) atomicAdd(s_set_count, 1u);
            }
            if (key == 0u || key == l) break;
            slot = (slot + 1u) % SET_SLOTS;
        }
    }
    barrier();
    const uint collected = s_set_count;  // uniform
    if (s_has_zero != 0u && collected != 0u) {  // uniform; otherwise nothing changes
        if (collected <= SET_MAX) {
            if (lid < SET_SLOTS && s_set[lid] != 0u) {
                const uint key = s_set[lid];
                uint rank = 0u;
                for (uint i = 0u; i < SET_SLOTS; ++i) rank += s_set[i] != 0u && s_set[i] < key ? 1u : 0u;
                s_sorted[rank] = key;
            }
            barrier();
        }
        uint taken = 0u;  // collected instances done
        uint prev = 0u;   // chosen one by one: the instances above this one are still to do
        uint round = 0u;
        for (;;) {
            // The batch: the next (up to) 16 instances, ascending.
            uint count = 0u;
            if (collected <= SET_MAX) {
                count = min(collected - taken, uint(PG_CLOSE_BATCH));
                if (lid < count) s_list[lid] = s_sorted[taken + lid];
                taken += count;
            } else {
                for (;;) {
                    const uint slot = round % 3u;
                    uint best = 0xFFFFFFFFu;
                    bool found = false;
                    for (int k = 0; k < CELLS; ++k) {
                        const int row = row0 + 4 * k;
                        const bool in_window = col >= r && col < E - r && row >= r && row < E - r;
                        if (in_window && label[k] > prev) {
                            best = min(best, label[k]);
                            found = true;
                        }
                    }
                    if (found) {
                        atomicMin(s_next[slot], best);
                        atomicOr(s_found[slot], 1u);
                    }
                    if (lid == 0u) {  // the next slot was last read two choices ago
                        s_next[(round + 1u) % 3u] = 0xFFFFFFFFu;
                        s_found[(round + 1u) % 3u] = 0u;
                    }
                    barrier();
                    ++round;
                    if (s_found[slot] == 0u) break;  // uniform
                    prev = s_next[slot];
                    if (lid == 0u) s_list[count] = prev;
                    if (++count == PG_CLOSE_BATCH) break;
                }
                if (count == 0u) break;  // uniform
            }
            const uint rows = count * GRID;  // the batch's bit rows
            for (int t = 0; t < TASKS; ++t) {
                const uint i = lid + uint(t) * PG_CLOSE_THREADS;
                s_x[2u * i] = 0u;
                s_x[2u * i + 1u] = 0u;
            }
            if (lid < 2u * GRID) s_any[lid] = 0u;
            barrier();
            for (int k = 0; k < CELLS; ++k) {
                const int j = batch_index(label[k], count);
                const uint row = uint(row0 + 4 * k);
                if (j >= 0) atomicOr(s_x[2u * (uint(j) * GRID + row) + uint(col) / 32u], 1u << (uint(col) % 32u));
            }
            barrier();
            for (int t = 0; t < TASKS; ++t) {
                const uint i = lid + uint(t) * PG_CLOSE_THREADS;
                if (i >= rows || i % GRID >= uE) continue;
                const uvec2 a = dilate_row(x_row(i), ur);
                s_y[2u * i] = a.x;
                s_y[2u * i + 1u] = a.y;
            }
            barrier();
            for (int t = 0; t < TASKS; ++t) {
                const uint i = lid + uint(t) * PG_CLOSE_THREADS, row = i % GRID;
                if (i >= rows || row < ur || row >= uE - ur) continue;
                uvec2 a = uvec2(0xFFFFFFFFu);  // a row off the image: every pixel set
                const int y = ry + int(row);
                if (y >= 0 && y < h) {
                    a = outside;
                    for (uint d = 0u; d <= 2u * ur; ++d) a |= y_row(i - ur + d);
                }
                a = erode_row(a, ur);
                s_x[2u * i] = a.x;
                s_x[2u * i + 1u] = a.y;
            }
            barrier();
            for (int t = 0; t < TASKS; ++t) {
                const uint i = lid + uint(t) * PG_CLOSE_THREADS, row = i % GRID;
                if (i >= rows || row < 2u * ur || row >= uE - 2u * ur) continue;
                uvec2 a = uvec2(0xFFFFFFFFu);
                for (uint d = 0u; d <= 2u * ur; ++d) a &= x_row(i - ur + d);
                s_y[2u * i] = a.x;
                s_y[2u * i + 1u] = a.y;
                if (a.x != 0u) atomicOr(s_any[2u * row], a.x);
                if (a.y != 0u) atomicOr(s_any[2u * row + 1u], a.y);
            }
            barrier();
            // Unassigned 0-pixels take the first (smallest) instance whose closing holds them.
            const uint word = uint(col) / 32u, bit = 1u << (uint(col) % 32u);
            for (int k = 0; k < CELLS; ++k) {
                const uint row = uint(row0 + 4 * k);
                if (result[k] != 0u || (s_any[2u * row + word] & bit) == 0u) continue;
                // A cell runs this loop in one batch at most: the first that covers it.
                for (uint j = 0u; j < count; ++j)
                    if ((s_y[2u * (j * GRID + row) + word] & bit) != 0u) {
                        result[k] = s_list[j];
                        break;
                    }
            }
            if (count < PG_CLOSE_BATCH || taken == collected) break;  // uniform: no more instances
            barrier();  // the arrays and s_list are reused by the next batch
        }
    }
    // Only the tile's newly assigned pixels are written.
    for (int k = 0; k < CELLS; ++k) {
        const int row = row0 + 4 * k, x = rx + col, y = ry + row;
        const bool in_tile = col >= 2 * r && col < 2 * r + T && row >= 2 * r && row < 2 * r + T;
        if (in_tile && x < w && y < h && result[k] != label[k]) dst[y * w + x] = result[k];
    }
}

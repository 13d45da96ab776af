#version 450
// One closing radius for radii too large for refine_close (definition in
// engine/segment/mask_refine.h), over a wave of tiles. Each region pixel holds a uint of bits,
// bit j = the batch's j-th instance (batches of 32, ascending), in this workgroup's slice of a
// global scratch buffer; four separable passes between its two arrays:
//   m: instance bits of the region            E x E
//   a: row dilation, columns [r, E - r)        E x (T + 2r)
//   m: column dilation, rows [r, E - r)        (T + 2r) x (T + 2r), all ones outside the image
//   a: row erosion, columns [2r, E - 2r)       (T + 2r) x T
//   tile pixels: column erosion, then the smallest covering instance.
// Unlike refine_close, its loops grow with the radius and with the instances near a tile: on
// lavapipe, which ends a shader's loops after 65535 iterations in all, a tile with hundreds
// of instances within r of it can run out.
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "segment/refine_shared.h"

layout(local_size_x = PG_CLOSE_THREADS) in;
layout(std430, binding = 0) readonly buffer Src { uint src[]; };
layout(std430, binding = 1) buffer Dst { uint dst[]; };
layout(std430, binding = 2) coherent buffer Scratch { uint scratch[]; };
layout(push_constant) uniform Push { ClosePush pc; };

// Every (x, y) with 0 <= x < W, 0 <= y < H, spread over the workgroup as 16 x 16: strided 2D
// loops rather than one index, as integer division is slow on CPU devices (lavapipe).
#define PG_CLOSE_FOR_2D(X_, Y_, W_, H_)                                                      \
    for (int Y_ = int(gl_LocalInvocationIndex / PG_CLOSE_SIDE); Y_ < (H_); Y_ += PG_CLOSE_SIDE) \
        for (int X_ = int(gl_LocalInvocationIndex % PG_CLOSE_SIDE); X_ < (W_); X_ += PG_CLOSE_SIDE)

shared uint s_list[PG_CLOSE_GLOBAL_BATCH];  // the batch's instances, ascending
shared uint s_next;  // smallest candidate above the last one taken
shared uint s_found;
shared uint s_has_zero;

// Copies the tile from src to dst; whether it holds a 0-pixel (else it is done).
bool close_copy_tile(int x0, int y0, int T) {
    const int w = int(pc.width), h = int(pc.height);
    if (gl_LocalInvocationIndex == 0u) s_has_zero = 0u;
    barrier();
    PG_CLOSE_FOR_2D(lx, ly, T, T) {
        const int x = x0 + lx, y = y0 + ly;
        if (x >= w || y >= h) continue;
        const uint l = src[y * w + x];
        dst[y * w + x] = l;
        if (l == 0u) atomicOr(s_has_zero, 1u);
    }
    barrier();
    return s_has_zero != 0u;
}

// The next (up to) `batch` instances above `prev` within r of the tile, ascending, into
// s_list; returns how many and advances `prev`. A pixel can only join an instance that has a
// pixel within r of it, so no other instance matters to the tile.
uint close_next_batch(inout uint prev, uint batch, int x0, int y0, int T) {
    const int w = int(pc.width), h = int(pc.height), r = int(pc.radius), win = T + 2 * r;
    uint count = 0u;
    for (uint j = 0u; j < batch; ++j) {
        if (gl_LocalInvocationIndex == 0u) {
            s_next = 0xFFFFFFFFu;
            s_found = 0u;
        }
        barrier();
        uint best = 0xFFFFFFFFu;
        bool any = false;
        PG_CLOSE_FOR_2D(wx, wy, win, win) {
            const int x = x0 - r + wx, y = y0 - r + wy;
            if (x < 0 || y < 0 || x >= w || y >= h) continue;
            const uint l = src[y * w + x];
            if (l > prev) {
                best = min(best, l);
                any = true;
            }
        }
        if (any) {
            atomicMin(s_next, best);
            atomicOr(s_found, 1u);
        }
        barrier();
        const bool found = s_found != 0u;
        const uint next = s_next;
        barrier();  // everybody has read them before the next round resets them
        if (!found) break;  // uniform
        if (gl_LocalInvocationIndex == 0u) s_list[j] = next;
        prev = next;
        count = j + 1u;
    }
    barrier();  // s_list complete
    return count;
}

// Index of `label` in s_list[0..count), or -1: a binary search with a fixed trip count.
int close_batch_index(uint label, uint count) {
    if (label == 0u || label < s_list[0] || label > s_list[count - 1u]) return -1;
    uint lo = 0u;
    for (uint step = PG_CLOSE_GLOBAL_BATCH / 2u; step > 0u; step >>= 1u)
        if (lo + step < count && s_list[lo + step] <= label) lo += step;
    return s_list[lo] == label ? int(lo) : -1;
}


uint g_m, g_a;  // this workgroup's two arrays in the scratch buffer
#define M(i) scratch[g_m + uint(i)]
#define A(i) scratch[g_a + uint(i)]
void sync_scratch() {
    memoryBarrierBuffer();
    barrier();
}

void main() {
    const uint tile = pc.tile_base + pg_group_index();
    if (tile >= pc.tile_count) return;  // the folded grid's spare groups: whole workgroups
    const uint lid = gl_LocalInvocationIndex;
    const int w = int(pc.width), h = int(pc.height), r = int(pc.radius), T = int(pc.tile);
    const int x0 = int(tile % pc.tiles_x) * T, y0 = int(tile / pc.tiles_x) * T;
    const int E = T + 4 * r, Wa = T + 2 * r, win = 2 * r + 1;
    g_m = pg_group_index() * pc.scratch_words;
    g_a = g_m + uint(E * E);

    if (!close_copy_tile(x0, y0, T)) return;  // uniform
    uint prev = 0u;
    for (;;) {
        const uint count = close_next_batch(prev, PG_CLOSE_GLOBAL_BATCH, x0, y0, T);
        if (count == 0u) break;
        // m: which of the batch's instances each region pixel holds; nothing outside.
        PG_CLOSE_FOR_2D(c, row, E, E) {
            const int x = x0 - 2 * r + c, y = y0 - 2 * r + row;
            uint bits = 0u;
            if (x >= 0 && y >= 0 && x < w && y < h) {
                const int b = close_batch_index(src[y * w + x], count);
                if (b >= 0) bits = 1u << uint(b);
            }
            M(row * E + c) = bits;
        }
        sync_scratch();
        PG_CLOSE_FOR_2D(c, row, Wa, E) {
            uint v = 0u;
            for (int d = 0; d < win; ++d) v |= M(row * E + c + d);
            A(row * Wa + c) = v;
        }
        sync_scratch();
        PG_CLOSE_FOR_2D(c, row, Wa, Wa) {
            const int x = x0 - r + c, y = y0 - r + row;
            uint v = 0xFFFFFFFFu;  // outside the image: every instance, for the erosion
            if (x >= 0 && y >= 0 && x < w && y < h) {
                v = 0u;
                for (int d = 0; d < win; ++d) v |= A((row + d) * Wa + c);
            }
            M(row * Wa + c) = v;
        }
        sync_scratch();
        PG_CLOSE_FOR_2D(c, row, T, Wa) {
            uint v = 0xFFFFFFFFu;
            for (int d = 0; d < win; ++d) v &= M(row * Wa + c + d);
            A(row * T + c) = v;
        }
        sync_scratch();
        PG_CLOSE_FOR_2D(lx, ly, T, T) {
            const int x = x0 + lx, y = y0 + ly;
            if (x >= w || y >= h) continue;
            uint v = 0xFFFFFFFFu;
            for (int d = 0; d < win; ++d) v &= A((ly + d) * T + lx);
            // An earlier (smaller) batch's assignment stands; dst was written by this invocation.
            if (v != 0u && src[y * w + x] == 0u && dst[y * w + x] == 0u) dst[y * w + x] = s_list[findLSB(v)];
        }
        if (count < PG_CLOSE_GLOBAL_BATCH) break;  // uniform: no more instances
        sync_scratch();  // the arrays are reused by the next batch
    }
}

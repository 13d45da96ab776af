// Steps shared by the two closing kernels (refine_close, refine_close_global), one workgroup
// per output tile: the copy of the tile and the choice of the next batch of instances. The
// includer declares src, dst, pc (ClosePush) and defines PG_CLOSE_LIST (the batch size).
// Both functions contain barriers: call them in uniform control flow.
#ifndef PG_REFINE_CLOSE_TILE_GLSL
#define PG_REFINE_CLOSE_TILE_GLSL

// Every (x, y) with 0 <= x < W, 0 <= y < H, spread over the 16 x 16 workgroup. Strided 2D
// loops rather than one index: integer division is slow on CPU devices (lavapipe).
#define PG_CLOSE_FOR_2D(X_, Y_, W_, H_)                                          \
    for (int Y_ = int(gl_LocalInvocationIndex / PG_CLOSE_SIDE); Y_ < (H_); Y_ += PG_CLOSE_SIDE)  \
        for (int X_ = int(gl_LocalInvocationIndex % PG_CLOSE_SIDE); X_ < (W_); X_ += PG_CLOSE_SIDE)

#define PG_CLOSE_FOR_1D(X_, Y_, W_, H_) for (int i_ = int(gl_LocalInvocationIndex), X_ = i_ % (W_), Y_ = i_ / (W_); i_ < (W_) * (H_); i_ += 256, X_ = i_ % (W_), Y_ = i_ / (W_))
shared uint s_list[PG_CLOSE_LIST];  // the batch's instances, ascending
shared uint s_next;                 // smallest candidate above the last one taken
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
        const int span = (win + PG_CLOSE_SIDE - 1) / PG_CLOSE_SIDE * PG_CLOSE_SIDE;
        PG_CLOSE_FOR_2D(wx, wy, span, span) {
            const int x = x0 - r + wx, y = y0 - r + wy;
            if (wx >= win || wy >= win || x < 0 || y < 0 || x >= w || y >= h) continue;
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
    for (uint step = PG_CLOSE_LIST / 2u; step > 0u; step >>= 1u)
        if (lo + step < count && s_list[lo + step] <= label) lo += step;
    return s_list[lo] == label ? int(lo) : -1;
}

#endif

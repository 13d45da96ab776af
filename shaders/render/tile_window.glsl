// The part of a tile's list [full.x, full.y) that this dispatch walks: window `index` of
// `planned` (kTileWindow keys each; render_shared.h says why). A tile whose list ended in an
// earlier window is inactive. A tile whose list goes on past the last planned window is lost:
// it writes nothing, and the host records the frame again with enough windows.
#ifndef PG_TILE_WINDOW_GLSL
#define PG_TILE_WINDOW_GLSL

struct TileWindow {
    uvec2 range;  // keys of this window
    bool first;   // the first window: the pixel starts fresh (or from the last slab's carry)
    bool last;    // the tile's list ends in this window
    bool skip;    // inactive or lost: the group returns at once
};

#if !defined(PG_TILE_WINDOWS)
#error "define PG_TILE_WINDOWS (0: one window holds every list, 1: windows) before including tile_window.glsl"
#elif PG_TILE_WINDOWS == 0
// The frame was planned with one window: every tile's whole list, fresh or from the last slab.
// Constant flags let the compiler drop the window carry; on lavapipe the windowed variant's
// extra state cost the blend ~10 % though it walked the same keys.
TileWindow tile_window(uvec2 full, uint index, uint planned) { return TileWindow(full, true, true, false); }
#else
TileWindow tile_window(uvec2 full, uint index, uint planned) {
    const uint len = full.y - full.x, off = index * kTileWindow;
    TileWindow t;
    t.first = index == 0u;
    t.range = uvec2(full.x + min(off, len), full.x + min(len, off + kTileWindow));
    t.last = t.range.y == full.y;
    const bool inactive = !t.first && off >= len;
    const bool lost = !t.last && index + 1u >= planned;
    t.skip = inactive || lost;
    return t;
}
#endif

#endif

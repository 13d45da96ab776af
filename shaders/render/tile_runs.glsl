// Per-run lists of a tile's staged Gaussians, shared by render/blend and segment/label_occlusion.
// An invocation draws PG_RUN_ROWS pixels of one column (1 unless the including shader says
// otherwise): invocation i of the tile's kBlendGroup / PG_RUN_ROWS draws rows
// (i / 16) * PG_RUN_ROWS + 0 .. PG_RUN_ROWS - 1 of column i % 16. The tile's invocations form
// kRuns runs of 8 consecutive ones (run r: 8 columns (r % 2) * 8 .. + 7 by PG_RUN_ROWS rows from
// (r / 2) * PG_RUN_ROWS). For each staged batch, run r's list holds, in depth order, the batch
// positions of the Gaussians whose support ellipse reaches a pixel centre of the run: byte t of
// the list is byte (t % 4) of s_run_list[r * 64 + t / 4]. Each invocation loops over its own
// run's list, so drivers that run masked lanes in lockstep (lavapipe) do no work for Gaussians
// that miss the run; the result is the same for any subgroup size. Outside the ellipse alpha <
// 1/255, so the skipping is exact.
#ifndef PG_TILE_RUNS_GLSL
#define PG_TILE_RUNS_GLSL

#ifndef PG_RUN_ROWS
#define PG_RUN_ROWS 1
#endif
const uint kRowRuns = kBlendGroup / 8u;  // 8x1 pieces of the tile
const uint kRuns = kRowRuns / PG_RUN_ROWS;
shared uint s_runs[kBlendGroup];  // by batch position: which runs the support reaches (bit r)
shared uint s_run_list[kRuns * (kBlendGroup / 4u)];
shared uint s_run_count[kRuns];

// Pixel r (0 .. PG_RUN_ROWS - 1) of this invocation, in the image.
uvec2 tile_runs_pixel(uint r) {
    const uint lid = gl_LocalInvocationIndex;
    return gl_WorkGroupID.xy * kTileSize + uvec2(lid % kTileSize, (lid / kTileSize) * PG_RUN_ROWS + r);
}

// The runs of the tile with pixel origin `origin` that splat `sp`'s support ellipse reaches.
uint tile_runs_reached(Splat sp, uvec2 origin) {
    uint runs = 0u;
    for (uint r = 0u; r < 32u; ++r) {
        float y = float(origin.y + (r >> 1)) + 0.5;
        float x0 = float(origin.x + (r & 1u) * 8u) + 0.5;
        float dy = y - sp.mean.y;
        float x = clamp(sp.mean.x - sp.conic.y * dy / sp.conic.x, x0, x0 + 7.0);
        if (pg_form(sp.conic.xyz, vec2(x - sp.mean.x, dy)) <= sp.conic.w) runs |= 1u << r;
    }
#if PG_RUN_ROWS > 1
    // 8x1 piece r (row r / 2, half r % 2) belongs to run (r / 2 / PG_RUN_ROWS) * 2 + r % 2.
    uint folded = 0u;
    for (uint r = 0u; r < 32u; ++r)
        if ((runs & (1u << r)) != 0u) folded |= 1u << ((r >> 1) / PG_RUN_ROWS * 2u + (r & 1u));
    runs = folded;
#endif
    return runs;
}

// Every invocation calls this between two barriers once s_runs holds the batch's first `count`
// entries: invocations 0 .. kRuns - 1 each build one run's list (the tile has at least kRuns).
void tile_runs_build(uint count) {
    if (gl_LocalInvocationIndex >= kRuns) return;
    uint r = gl_LocalInvocationIndex, bit = 1u << r, n = 0u, word = 0u;
    for (uint j = 0u; j < count; ++j) {
        if ((s_runs[j] & bit) == 0u) continue;
        word |= j << ((n & 3u) * 8u);
        ++n;
        if ((n & 3u) == 0u) {
            s_run_list[r * (kBlendGroup / 4u) + (n >> 2) - 1u] = word;
            word = 0u;
        }
    }
    if ((n & 3u) != 0u) s_run_list[r * (kBlendGroup / 4u) + (n >> 2)] = word;
    s_run_count[r] = n;
}

// The word of run `run`'s list that holds entry t (and the three beside it: byte t % 4).
uint tile_runs_word(uint run, uint t) { return s_run_list[run * (kBlendGroup / 4u) + (t >> 2)]; }

// Entry t of run `run`'s list: a batch position.
uint tile_runs_entry(uint run, uint t) { return (s_run_list[run * (kBlendGroup / 4u) + (t >> 2)] >> ((t & 3u) * 8u)) & 0xFFu; }

#endif

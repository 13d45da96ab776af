// Whether a Gaussian's support ellipse {p : (p-m)^T Q (p-m) <= r2} reaches any pixel centre
// of a tile. The minimum of the convex form over the box of the tile's pixel centres is 0 if
// m is inside, else it lies on an edge, where the 1D minimiser is clamped to the edge.
#ifndef PG_TILE_TEST_GLSL
#define PG_TILE_TEST_GLSL

// `precise` keeps the compiler from fusing differently in preprocess and emit_keys, which
// must take the same decision for every tile.
float pg_form(vec3 q, vec2 d) {
    precise float r = q.x * d.x * d.x + 2.0 * q.y * d.x * d.y + q.z * d.y * d.y;
    return r;
}

// q = (a, b, c) of the symmetric matrix [[a, b], [b, c]] (the conic with b not negated).
bool pg_ellipse_hits_tile(vec2 m, vec3 q, float r2, uvec2 tile, uvec2 image_size) {
    vec2 lo = vec2(tile * kTileSize) + 0.5;
    vec2 hi = min(vec2((tile + 1u) * kTileSize), vec2(image_size)) - 0.5;
    if (all(greaterThanEqual(m, lo)) && all(lessThanEqual(m, hi))) return true;
    float best = 3.4e38;
    // Horizontal edges: y fixed, minimise over x.
    for (int e = 0; e < 2; ++e) {
        precise float dy = (e == 0 ? lo.y : hi.y) - m.y;
        precise float x = clamp(m.x - q.y * dy / q.x, lo.x, hi.x);
        best = min(best, pg_form(q, vec2(x - m.x, dy)));
    }
    // Vertical edges: x fixed, minimise over y.
    for (int e = 0; e < 2; ++e) {
        precise float dx = (e == 0 ? lo.x : hi.x) - m.x;
        precise float y = clamp(m.y - q.y * dx / q.z, lo.y, hi.y);
        best = min(best, pg_form(q, vec2(dx, y - m.y)));
    }
    return best <= r2;
}
#endif

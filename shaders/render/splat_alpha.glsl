// A splat's alpha at a pixel centre, as the 3DGS rasterizer takes it (clamped to kAlphaMax), and
// whether it blends there: inside its footprint and at least kAlphaMin. One rule for every pass
// that walks a tile's list (blend, picking, label occlusion), so that they agree on which
// Gaussians a pixel sees.
#ifndef PG_SPLAT_ALPHA_GLSL
#define PG_SPLAT_ALPHA_GLSL

float splat_alpha(vec2 mean, float opacity, vec3 conic, vec2 center, out bool use) {
    vec2 d = mean - center;
    float power = -0.5 * (conic.x * d.x * d.x + conic.z * d.y * d.y) - conic.y * d.x * d.y;
    float alpha = min(kAlphaMax, opacity * exp(min(power, 0.0)));
    use = power <= 0.0 && alpha >= kAlphaMin;
    return alpha;
}

#endif

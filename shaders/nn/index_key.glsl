// 64-bit keys as uvec2 (x: low word, y: high word): the layout of U64 tensors and of
// engine/sort's 64-bit keys. No shaderInt64 needed.
#ifndef PG_NN_INDEX_KEY_GLSL
#define PG_NN_INDEX_KEY_GLSL

// v << s as a 64-bit value (bits past 64 are lost).
uvec2 key_shl(uint v, uint s) {
    if (s == 0u) return uvec2(v, 0u);
    if (s < 32u) return uvec2(v << s, v >> (32u - s));
    if (s < 64u) return uvec2(0u, v << (s - 32u));
    return uvec2(0u);
}

uvec2 key_shr(uvec2 k, uint s) {
    if (s == 0u) return k;
    if (s < 32u) return uvec2((k.x >> s) | (k.y << (32u - s)), k.y >> s);
    if (s < 64u) return uvec2(k.y >> (s - 32u), 0u);
    return uvec2(0u);
}

bool key_less(uvec2 a, uvec2 b) { return a.y < b.y || (a.y == b.y && a.x < b.x); }

uint bit_length(uint v) { return v == 0u ? 0u : uint(findMSB(v)) + 1u; }

// Bit widths of x, y, z, batch from their maxima.
uvec4 grid_widths(uvec4 maxima) {
    return uvec4(bit_length(maxima.x), bit_length(maxima.y), bit_length(maxima.z), bit_length(maxima.w));
}

// (batch, x, y, z) packed most significant first, so key order is lexicographic order.
uvec2 grid_key(uvec4 widths, uvec3 p, uint batch) {
    uint zy = widths.z + widths.y;
    return key_shl(batch, zy + widths.x) | key_shl(p.x, zy) | key_shl(p.y, widths.z) | uvec2(p.z, 0u);
}

#endif

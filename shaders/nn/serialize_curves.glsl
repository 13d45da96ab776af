// Pointcept's space-filling curves on `depth` bits per axis (bits above are ignored), as
// 64-bit uvec2 codes. Needs index_key.glsl.
#ifndef PG_NN_SERIALIZE_CURVES_GLSL
#define PG_NN_SERIALIZE_CURVES_GLSL

// Bit i of x, y, z goes to bits 3i+2, 3i+1, 3i.
uvec2 z_order(uvec3 p, uint depth) {
    uvec2 code = uvec2(0u);
    for (uint i = 0u; i < depth; ++i) {
        uvec3 b = (p >> i) & 1u;
        code |= key_shl((b.x << 2u) | (b.y << 1u) | b.z, 3u * i);
    }
    return code;
}

// Each bit becomes the xor of itself and every higher bit of the word.
uint prefix_xor(uint w) {
    w ^= w >> 1u;
    w ^= w >> 2u;
    w ^= w >> 4u;
    w ^= w >> 8u;
    w ^= w >> 16u;
    return w;
}

// Skilling's axes-to-transpose (without its final Gray step), MSB-first interleave, then
// Gray to binary over all 64 bits: bit for bit what Pointcept's hilbert.encode computes.
uvec2 hilbert(uvec3 p, uint depth) {
    uint X[3] = uint[3](p.x, p.y, p.z);
    for (int q = int(depth) - 1; q >= 1; --q) {
        uint Q = 1u << uint(q), P = Q - 1u;
        for (int i = 0; i < 3; ++i) {
            if ((X[i] & Q) != 0u) {
                X[0] ^= P;
            } else {
                uint t = (X[0] ^ X[i]) & P;
                X[0] ^= t;
                X[i] ^= t;
            }
        }
    }
    // Bit q of axis i to bit 3q + 2 - i is the z-order interleave.
    uvec2 h = z_order(uvec3(X[0], X[1], X[2]), depth);
    uint carry = (bitCount(h.y) & 1u) != 0u ? 0xFFFFFFFFu : 0u;
    return uvec2(prefix_xor(h.x) ^ carry, prefix_xor(h.y));
}

#endif

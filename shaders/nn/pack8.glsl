// 8 floats as one u64vec4 (low word first): the CPU kernels' loads and stores, where a load is
// a per-lane loop per component and 64-bit components halve the loops. Needs
// GL_EXT_shader_explicit_arithmetic_types_int64 enabled by the including shader.
#ifndef PG_PACK8_GLSL
#define PG_PACK8_GLSL

void unpack8(u64vec4 x, out vec4 lo, out vec4 hi) {
    lo = uintBitsToFloat(uvec4(unpackUint2x32(x.x), unpackUint2x32(x.y)));
    hi = uintBitsToFloat(uvec4(unpackUint2x32(x.z), unpackUint2x32(x.w)));
}

u64vec4 pack8(vec4 lo, vec4 hi) {
    const uvec4 a = floatBitsToUint(lo), b = floatBitsToUint(hi);
    return u64vec4(packUint2x32(a.xy), packUint2x32(a.zw), packUint2x32(b.xy), packUint2x32(b.zw));
}

#endif

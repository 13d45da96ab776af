// The graph's uniform grid: cells clamp at the robust bounds, keys pack the coordinates.
#ifndef PG_GRAPH_GRID_GLSL
#define PG_GRAPH_GRID_GLSL
ivec3 cell_of(vec3 p, vec4 origin, uvec4 dims) {
    return clamp(ivec3(floor((p - origin.xyz) * origin.w)), ivec3(0), ivec3(dims.xyz) - 1);
}
uint cell_key(ivec3 c, uvec4 bits) { return uint(c.x) | (uint(c.y) << bits.x) | (uint(c.z) << (bits.x + bits.y)); }
#endif

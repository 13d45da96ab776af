// The per-instance table of the largest-component stage: open addressing with linear probing,
// keyed by instance id (0 = free slot). It has at least as many slots as pixels, so it never
// fills up.
#ifndef PG_REFINE_LCC_TABLE_GLSL
#define PG_REFINE_LCC_TABLE_GLSL
uint lcc_hash(uint x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}
#endif

// Lock-free union-find over the pixel array `parent` (a coherent storage buffer or a shared
// array the includer declares), after ECL-CC (Jaiganesh and Burtscher, 2018). A root is
// linked under a smaller root by compare-and-swap, which fails if it stopped being a root
// meanwhile; other entries only ever move to an ancestor (path halving, plain stores). So every
// chain descends, find terminates, and the root of a finished tree is its smallest index.
#ifndef PG_REFINE_UNION_FIND_GLSL
#define PG_REFINE_UNION_FIND_GLSL

uint uf_find(uint x) {
    for (;;) {
        const uint p = parent[x];
        if (p == x) return x;
        const uint g = parent[p];
        if (g == p) return p;
        parent[x] = g;  // x skips a generation: g is an ancestor whatever happened since
        x = g;
    }
}

void uf_union(uint a, uint b) {
    a = uf_find(a);
    b = uf_find(b);
    while (a != b) {
        if (a > b) {
            const uint t = a;
            a = b;
            b = t;
        }
        const uint old = atomicCompSwap(parent[b], b, a);
        if (old == b) return;
        // b was linked under another root meanwhile: join the two trees' current roots.
        b = uf_find(old);
        a = uf_find(a);
    }
}

// Whether pixels with these labels belong together under `mode` (refine_shared.h).
bool cc_joined(uint mode, uint a, uint b) {
    return mode == PG_CC_ZERO_4 ? (a == 0u && b == 0u) : (a != 0u && a == b);
}
bool cc_member(uint mode, uint a) { return mode == PG_CC_ZERO_4 ? a == 0u : a != 0u; }

#endif

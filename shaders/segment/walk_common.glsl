// Shared by the random walker's node passes: a node's label columns as WALK_VECS vec4s (as few
// as the solve's labels need: the passes' memory traffic follows the labels), and the
// per-workgroup partial dot products (one per column) that walk_reduce sums.
#ifndef PG_WALK_COMMON_GLSL
#define PG_WALK_COMMON_GLSL
// vec4s per node in the column buffers (requires the WalkPush as pc); at most kWalkVecs.
#define WALK_VECS ((pc.size.z + 3u) / 4u)
shared vec4 s_dot[kWalkVecs][kGraphGroup];

// Every invocation of the group calls this (barriers inside) with its node's terms (0 if none);
// a tree reduction, then partials[group * kWalkVecs + c].
#define WALK_STORE_PARTIALS(terms, partials)                                                      \
    {                                                                                             \
        uint t_ = gl_LocalInvocationIndex;                                                        \
        for (uint c_ = 0u; c_ < kWalkVecs; ++c_) s_dot[c_][t_] = terms[c_];                       \
        barrier();                                                                                \
        for (uint stride_ = kGraphGroup / 2u; stride_ > 0u; stride_ >>= 1) {                      \
            if (t_ < stride_)                                                                     \
                for (uint c_ = 0u; c_ < kWalkVecs; ++c_) s_dot[c_][t_] += s_dot[c_][t_ + stride_]; \
            barrier();                                                                            \
        }                                                                                         \
        if (t_ < kWalkVecs) partials[pg_group_index() * kWalkVecs + t_] = s_dot[t_][0];           \
    }
#endif

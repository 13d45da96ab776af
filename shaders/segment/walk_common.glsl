// Shared by the random walker's node passes: a node's label columns as WALK_VECS vec4s (as few
// as the solve's labels need: the passes' memory traffic follows the labels), and the
// per-workgroup partial dot products (one per column) that walk_reduce sums.
#ifndef PG_WALK_COMMON_GLSL
#define PG_WALK_COMMON_GLSL
// vec4s per node in the column buffers, at most kWalkVecs: fixed per build (shaders/CMakeLists.txt),
// so the loops over a node's columns unroll.
#ifndef WALK_VECS
#error "WALK_VECS: built per column count (shaders/CMakeLists.txt)"
#endif
shared vec4 s_dot[WALK_VECS][kGraphGroup];

// Every invocation of the group calls this (barriers inside) with its node's terms (0 if none);
// then partials[group * kWalkVecs + c] for the solve's c < WALK_VECS (walk_reduce reads no
// others: summing kWalkVecs columns cost a 1-vec solve ~4 % of its GPU time). Two raking steps
// rather than a tree: CPU Vulkan runs every invocation through every stretch between barriers,
// so each barrier costs a whole pass over the group (a tree's eight made the reduction cost more
// than the sparse product).
shared vec4 s_rake[WALK_VECS][16];
#define WALK_STORE_PARTIALS(terms, partials)                                                      \
    {                                                                                             \
        uint t_ = gl_LocalInvocationIndex;                                                        \
        for (uint c_ = 0u; c_ < WALK_VECS; ++c_) s_dot[c_][t_] = terms[c_];                       \
        barrier();                                                                                \
        if (t_ < 16u * WALK_VECS) {                                                               \
            uint c_ = t_ / 16u, q_ = (t_ % 16u) * 16u;                                            \
            vec4 sum_ = vec4(0.0);                                                                \
            for (uint u_ = 0u; u_ < 16u; ++u_) sum_ += s_dot[c_][q_ + u_];                        \
            s_rake[c_][t_ % 16u] = sum_;                                                          \
        }                                                                                         \
        barrier();                                                                                \
        if (t_ < WALK_VECS) {                                                                     \
            vec4 sum_ = vec4(0.0);                                                                \
            for (uint u_ = 0u; u_ < 16u; ++u_) sum_ += s_rake[t_][u_];                            \
            partials[pg_group_index() * kWalkVecs + t_] = sum_;                                   \
        }                                                                                         \
    }
#endif

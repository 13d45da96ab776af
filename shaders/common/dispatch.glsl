// Linear ids for 1D work that the host folded into a 2D grid when it exceeded the
// device's group-count limit (engine/vk/commands.cpp).
#ifndef PG_DISPATCH_GLSL
#define PG_DISPATCH_GLSL
uint pg_group_index() { return gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x; }
// A macro, so gl_WorkGroupSize is the one of the including shader's local_size layout.
#define pg_global_index() (pg_group_index() * gl_WorkGroupSize.x + gl_LocalInvocationIndex)
// Writes indirect dispatch arguments for `groups` 1D groups, folded like the host does.
#define PG_WRITE_DISPATCH(buf, base, groups, limit)                         \
    {                                                                       \
        uint g_ = (groups), l_ = (limit);                                   \
        buf[(base) + 0] = g_ <= l_ ? max(g_, 1u) : l_;                      \
        buf[(base) + 1] = g_ <= l_ ? 1u : (g_ + l_ - 1u) / l_;              \
        buf[(base) + 2] = g_ == 0u ? 0u : 1u;                               \
    }
#endif

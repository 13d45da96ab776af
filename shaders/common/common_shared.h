// Push-constant layouts of the shared kernels in shaders/common, for the C++ that dispatches
// them (engine/render, tests/vk): one definition, no drift. Only 32-bit members, so C++ and
// std430 agree.
#ifndef PG_COMMON_SHARED_H
#define PG_COMMON_SHARED_H

#ifdef __cplusplus
#include <cstdint>
namespace pg::vk::gpu {
using uint = uint32_t;
#endif

// common/fill_u32: data[i] = value + i for i < n.
struct FillPush {
    uint n;
    uint value;
};

// common/indirect_args: a GPU-written count becomes the arguments of an indirect dispatch.
struct IndirectArgsPush {
    uint count_index;      // which count
    uint items_per_group;  // items one workgroup handles
    uint limit;            // the device's group-count limit along x
    uint args_index;       // where the three uints go
    uint clamp_count;      // counts are clamped to this (buffer capacity); 0 = no clamp
};

#ifdef __cplusplus
static_assert(sizeof(FillPush) == 8);
static_assert(sizeof(IndirectArgsPush) == 20);
}  // namespace pg::vk::gpu
#endif
#endif

#pragma once
// What each binding of set 0 of a compute shader is, read from its SPIR-V: a storage buffer
// (the common case) or a storage texel buffer (`imageBuffer` with a format qualifier). On CPU
// drivers (lavapipe) a texel load is gathered in vector code, where a storage-buffer load whose
// address differs between lanes is a loop over the lanes; kernels whose time goes to such
// gathers (sparse products over a graph's neighbours) read them through texel buffers.
#include <cstdint>
#include <span>
#include <vector>

#include <vulkan/vulkan.h>

namespace pg::vk {

struct BindingKind {
    VkDescriptorType type = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    VkFormat format = VK_FORMAT_UNDEFINED;  // texel buffers: the shader's format qualifier
    uint32_t texel_bytes = 0;
};

// Kinds of bindings 0..count-1 (bindings the shader does not declare are storage buffers).
// Throws std::runtime_error on a texel buffer of a format not supported here (32-bit channels,
// one or four of them).
std::vector<BindingKind> spirv_bindings(std::span<const uint32_t> code, uint32_t count);

}  // namespace pg::vk

#include "engine/vk/spirv_bindings.h"

#include <stdexcept>
#include <string>
#include <unordered_map>

namespace pg::vk {

namespace {
// The few SPIR-V opcodes and enumerants the scan needs (SPIR-V 1.x specification, section 3).
constexpr uint32_t kOpTypeImage = 25, kOpTypePointer = 32, kOpVariable = 59, kOpDecorate = 71;
constexpr uint32_t kDecorationBinding = 33, kDimBuffer = 5, kSampledStorage = 2;

struct Format {
    VkFormat format;
    uint32_t bytes;
};

// SPIR-V Image Format -> Vulkan format.
bool texel_format(uint32_t spirv_format, Format& out) {
    switch (spirv_format) {
        case 1: out = {VK_FORMAT_R32G32B32A32_SFLOAT, 16}; return true;   // Rgba32f
        case 3: out = {VK_FORMAT_R32_SFLOAT, 4}; return true;             // R32f
        case 21: out = {VK_FORMAT_R32G32B32A32_SINT, 16}; return true;    // Rgba32i
        case 24: out = {VK_FORMAT_R32_SINT, 4}; return true;              // R32i
        case 30: out = {VK_FORMAT_R32G32B32A32_UINT, 16}; return true;    // Rgba32ui
        case 33: out = {VK_FORMAT_R32_UINT, 4}; return true;              // R32ui
        default: return false;
    }
}
}  // namespace

std::vector<BindingKind> spirv_bindings(std::span<const uint32_t> code, uint32_t count) {
    std::vector<BindingKind> kinds(count);
    std::unordered_map<uint32_t, uint32_t> binding_of, pointee, var_type, buffer_image_format;
    for (size_t i = 5; i < code.size();) {
        const uint32_t words = code[i] >> 16, op = code[i] & 0xFFFF;
        if (words == 0 || i + words > code.size()) throw std::runtime_error("malformed SPIR-V");
        const uint32_t* w = &code[i];
        if (op == kOpDecorate && words >= 4 && w[2] == kDecorationBinding) binding_of[w[1]] = w[3];
        else if (op == kOpTypeImage && words >= 9 && w[3] == kDimBuffer && w[7] == kSampledStorage)
            buffer_image_format[w[1]] = w[8];
        else if (op == kOpTypePointer && words >= 4) pointee[w[1]] = w[3];
        else if (op == kOpVariable && words >= 4) var_type[w[2]] = w[1];
        i += words;
    }
    for (const auto& [var, binding] : binding_of) {
        if (binding >= count || !var_type.count(var) || !pointee.count(var_type[var])) continue;
        const auto image = buffer_image_format.find(pointee[var_type[var]]);
        if (image == buffer_image_format.end()) continue;
        Format f;
        if (!texel_format(image->second, f))
            throw std::runtime_error("texel buffer at binding " + std::to_string(binding) + " has SPIR-V image format " +
                                     std::to_string(image->second) + ", not one of r32f/r32i/r32ui/rgba32f/rgba32i/rgba32ui");
        kinds[binding] = {VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER, f.format, f.bytes};
    }
    return kinds;
}

}  // namespace pg::vk

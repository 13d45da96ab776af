#pragma once
// Embedded SPIR-V of every compute shader, by path under shaders/ without ".comp".
#include <cstdint>
#include <span>
#include <string>

namespace pg::shaders {
std::span<const uint32_t> spirv(const std::string& name);
}

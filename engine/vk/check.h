#pragma once
// Turns a failed Vulkan call into an exception that says which call and why.
#include <stdexcept>
#include <string>

#include <vulkan/vulkan.h>

namespace pg::vk {

const char* result_name(VkResult r);

class VulkanError : public std::runtime_error {
public:
    VulkanError(const std::string& what, VkResult r) : std::runtime_error(what + " failed: " + result_name(r)), result(r) {}
    VkResult result;
};

inline void check(VkResult r, const char* what) {
    if (r != VK_SUCCESS) throw VulkanError(what, r);
}

}  // namespace pg::vk

#define PG_VK(call) ::pg::vk::check((call), #call)

#pragma once
// A compute pipeline from an embedded shader: buffers at bindings 0..n-1 of set 0 (pushed, so
// there are no descriptor pools to manage), storage buffers or the texel buffers the shader
// declares (spirv_bindings.h), and one push-constant block.
#include <cstdint>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/vk/spirv_bindings.h"

namespace pg::vk {

class Context;

class ComputePipeline {
public:
    ComputePipeline(Context& ctx, const std::string& shader, uint32_t buffer_count, uint32_t push_bytes);
    ~ComputePipeline();
    ComputePipeline(const ComputePipeline&) = delete;
    ComputePipeline& operator=(const ComputePipeline&) = delete;

    VkPipeline handle() const { return pipeline_; }
    VkPipelineLayout layout() const { return layout_; }
    uint32_t buffer_count() const { return buffer_count_; }
    const std::vector<BindingKind>& bindings() const { return bindings_; }
    uint32_t push_bytes() const { return push_bytes_; }
    const std::string& name() const { return name_; }

private:
    Context& ctx_;
    std::string name_;
    uint32_t buffer_count_, push_bytes_;
    std::vector<BindingKind> bindings_;
    VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
    VkPipelineLayout layout_ = VK_NULL_HANDLE;
    VkPipeline pipeline_ = VK_NULL_HANDLE;
};

}  // namespace pg::vk

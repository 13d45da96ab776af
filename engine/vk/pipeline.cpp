#include "engine/vk/pipeline.h"

#include <vector>

#include "engine/vk/check.h"
#include "engine/vk/context.h"
#include "shaders/shaders.h"

namespace pg::vk {

ComputePipeline::ComputePipeline(Context& ctx, const std::string& shader, uint32_t buffer_count, uint32_t push_bytes)
    : ctx_(ctx), name_(shader), buffer_count_(buffer_count), push_bytes_(push_bytes) {
    VkDevice dev = ctx.device();
    auto code = shaders::spirv(shader);
    bindings_ = spirv_bindings(code, buffer_count);
    std::vector<VkDescriptorSetLayoutBinding> bindings(buffer_count);
    for (uint32_t i = 0; i < buffer_count; ++i)
        bindings[i] = {i, bindings_[i].type, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
    VkDescriptorSetLayoutCreateInfo dci{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    dci.flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR;
    dci.bindingCount = buffer_count;
    dci.pBindings = bindings.data();
    PG_VK(vkCreateDescriptorSetLayout(dev, &dci, nullptr, &set_layout_));

    VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_bytes};
    VkPipelineLayoutCreateInfo lci{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    lci.setLayoutCount = 1;
    lci.pSetLayouts = &set_layout_;
    lci.pushConstantRangeCount = push_bytes ? 1 : 0;
    lci.pPushConstantRanges = &range;
    PG_VK(vkCreatePipelineLayout(dev, &lci, nullptr, &layout_));

    VkShaderModuleCreateInfo sci{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    sci.codeSize = code.size() * sizeof(uint32_t);
    sci.pCode = code.data();
    VkShaderModule module;
    PG_VK(vkCreateShaderModule(dev, &sci, nullptr, &module));

    VkComputePipelineCreateInfo pci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    pci.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    pci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    pci.stage.module = module;
    pci.stage.pName = "main";
    pci.layout = layout_;
    VkResult r = vkCreateComputePipelines(dev, VK_NULL_HANDLE, 1, &pci, nullptr, &pipeline_);
    vkDestroyShaderModule(dev, module, nullptr);
    check(r, ("creating pipeline " + shader).c_str());
}

ComputePipeline::~ComputePipeline() {
    VkDevice dev = ctx_.device();
    vkDestroyPipeline(dev, pipeline_, nullptr);
    vkDestroyPipelineLayout(dev, layout_, nullptr);
    vkDestroyDescriptorSetLayout(dev, set_layout_, nullptr);
}

}  // namespace pg::vk

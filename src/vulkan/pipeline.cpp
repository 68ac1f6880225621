// Compute pipelines: descriptor-set layout of storage buffers, push constants, shader module.
#include "vulkan/pipeline.hpp"

#include <vector>

#include "base/trace.hpp"
#include "vulkan/check.hpp"
#include "vulkan/context.hpp"

namespace fdmsurf::detail {

ComputePipeline::ComputePipeline(const Context& ctx, const std::uint32_t* spirv, std::size_t bytes,
                                 std::uint32_t bindings, std::uint32_t push_bytes, const char* name)
    : ctx_(&ctx), spirv_(spirv), bytes_(bytes), bindings_(bindings), push_bytes_(push_bytes),
      name_(name) {
    if (push_bytes > ctx.limits().max_push_constants)
        throw Error(ErrorCode::DeviceLimit, std::string("pipeline ") + name + " needs " +
                                                std::to_string(push_bytes) +
                                                " bytes of push constants, the device allows " +
                                                std::to_string(ctx.limits().max_push_constants));
}

void ComputePipeline::create() const {
    const Context& ctx = *ctx_;
    device_ = ctx.device();
    const std::uint32_t bindings = bindings_, push_bytes = push_bytes_;
    const char* name = name_;
    VkShaderModule module = VK_NULL_HANDLE;
    try {
        std::vector<VkDescriptorSetLayoutBinding> b(bindings);
        for (std::uint32_t i = 0; i < bindings; ++i) {
            b[i].binding = i;
            b[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
            b[i].descriptorCount = 1;
            b[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
        }
        VkDescriptorSetLayoutCreateInfo set_info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
        set_info.bindingCount = bindings;
        set_info.pBindings = b.data();
        FDM_VK_CHECK(vkCreateDescriptorSetLayout(device_, &set_info, nullptr, &set_layout_));

        VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_bytes};
        VkPipelineLayoutCreateInfo layout_info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
        layout_info.setLayoutCount = 1;
        layout_info.pSetLayouts = &set_layout_;
        layout_info.pushConstantRangeCount = push_bytes ? 1 : 0;
        layout_info.pPushConstantRanges = &range;
        FDM_VK_CHECK(vkCreatePipelineLayout(device_, &layout_info, nullptr, &layout_));

        VkShaderModuleCreateInfo module_info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
        module_info.codeSize = bytes_;
        module_info.pCode = spirv_;
        FDM_VK_CHECK(vkCreateShaderModule(device_, &module_info, nullptr, &module));

        VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
        info.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
        info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
        info.stage.module = module;
        info.stage.pName = "main";
        info.layout = layout_;
        FDM_VK_CHECK(vkCreateComputePipelines(device_, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline_));
        vkDestroyShaderModule(device_, module, nullptr);
        module = VK_NULL_HANDLE;
        ctx.set_name(VK_OBJECT_TYPE_PIPELINE, reinterpret_cast<std::uint64_t>(pipeline_), name);
        if (trace_on()) trace((std::string("pipeline made: ") + name).c_str());
    } catch (...) {
        if (module) vkDestroyShaderModule(device_, module, nullptr);
        const_cast<ComputePipeline*>(this)->reset();
        throw;
    }
}

ComputePipeline& ComputePipeline::operator=(ComputePipeline&& o) noexcept {
    if (this != &o) {
        reset();
        ctx_ = std::exchange(o.ctx_, nullptr);
        spirv_ = std::exchange(o.spirv_, nullptr);
        bytes_ = std::exchange(o.bytes_, 0);
        device_ = std::exchange(o.device_, VK_NULL_HANDLE);
        set_layout_ = std::exchange(o.set_layout_, VK_NULL_HANDLE);
        layout_ = std::exchange(o.layout_, VK_NULL_HANDLE);
        pipeline_ = std::exchange(o.pipeline_, VK_NULL_HANDLE);
        bindings_ = std::exchange(o.bindings_, 0);
        push_bytes_ = std::exchange(o.push_bytes_, 0);
        name_ = std::exchange(o.name_, "");
    }
    return *this;
}

void ComputePipeline::reset() {
    if (!device_) return;
    if (pipeline_) vkDestroyPipeline(device_, pipeline_, nullptr);
    if (layout_) vkDestroyPipelineLayout(device_, layout_, nullptr);
    if (set_layout_) vkDestroyDescriptorSetLayout(device_, set_layout_, nullptr);
    pipeline_ = VK_NULL_HANDLE;
    layout_ = VK_NULL_HANDLE;
    set_layout_ = VK_NULL_HANDLE;
}

}  // namespace fdmsurf::detail

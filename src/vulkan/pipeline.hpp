// A compute pipeline built from embedded SPIR-V, with N storage-buffer bindings and push constants.
#pragma once

#include <vulkan/vulkan.h>

#include <cstddef>
#include <cstdint>
#include <utility>

namespace fdmsurf::detail {

class Context;

class ComputePipeline {
public:
    ComputePipeline() = default;
    // `spirv` and `bytes` from a shader embedded at build time (shaders/*.comp).
    ComputePipeline(const Context& ctx, const std::uint32_t* spirv, std::size_t bytes,
                    std::uint32_t bindings, std::uint32_t push_bytes, const char* name);
    ~ComputePipeline() { reset(); }
    ComputePipeline(ComputePipeline&& o) noexcept { *this = std::move(o); }
    ComputePipeline& operator=(ComputePipeline&& o) noexcept;
    ComputePipeline(const ComputePipeline&) = delete;
    ComputePipeline& operator=(const ComputePipeline&) = delete;

    VkPipeline handle() const { return pipeline_; }
    VkPipelineLayout layout() const { return layout_; }
    VkDescriptorSetLayout set_layout() const { return set_layout_; }
    std::uint32_t bindings() const { return bindings_; }
    std::uint32_t push_bytes() const { return push_bytes_; }
    const char* name() const { return name_; }
    void reset();

private:
    VkDevice device_ = VK_NULL_HANDLE;
    VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
    VkPipelineLayout layout_ = VK_NULL_HANDLE;
    VkPipeline pipeline_ = VK_NULL_HANDLE;
    std::uint32_t bindings_ = 0;
    std::uint32_t push_bytes_ = 0;
    const char* name_ = "";
};

}  // namespace fdmsurf::detail

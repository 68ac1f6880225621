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
    // `spirv` and `bytes` from a shader embedded at build time (shaders/*.comp), which must
    // outlive the object, as `ctx` must. The push-constant size is checked here; the Vulkan
    // objects are made on first use (handle(), layout(), set_layout() or make()), so that a run
    // whose stages all go to the host (a CPU device) compiles none of them (docs/performance.md).
    ComputePipeline(const Context& ctx, const std::uint32_t* spirv, std::size_t bytes,
                    std::uint32_t bindings, std::uint32_t push_bytes, const char* name);
    ~ComputePipeline() { reset(); }
    ComputePipeline(ComputePipeline&& o) noexcept { *this = std::move(o); }
    ComputePipeline& operator=(ComputePipeline&& o) noexcept;
    ComputePipeline(const ComputePipeline&) = delete;
    ComputePipeline& operator=(const ComputePipeline&) = delete;

    // Const, but they make the objects on first use: like the rest of an Engine, not to be used
    // from two threads at once.
    VkPipeline handle() const { return make(), pipeline_; }
    VkPipelineLayout layout() const { return make(), layout_; }
    VkDescriptorSetLayout set_layout() const { return make(), set_layout_; }
    std::uint32_t bindings() const { return bindings_; }
    std::uint32_t push_bytes() const { return push_bytes_; }
    const char* name() const { return name_; }
    bool made() const { return pipeline_ != VK_NULL_HANDLE; }
    // Makes the Vulkan objects now if not yet made (Engine::prepare warms the driver's cache so).
    // Throws Error(Vulkan) as the driver's calls fail.
    void make() const {
        if (pipeline_ == VK_NULL_HANDLE && ctx_ != nullptr) create();
    }
    void reset();

private:
    void create() const;
    const Context* ctx_ = nullptr;
    const std::uint32_t* spirv_ = nullptr;
    std::size_t bytes_ = 0;
    mutable VkDevice device_ = VK_NULL_HANDLE;
    mutable VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
    mutable VkPipelineLayout layout_ = VK_NULL_HANDLE;
    mutable VkPipeline pipeline_ = VK_NULL_HANDLE;
    std::uint32_t bindings_ = 0;
    std::uint32_t push_bytes_ = 0;
    const char* name_ = "";
};

}  // namespace fdmsurf::detail

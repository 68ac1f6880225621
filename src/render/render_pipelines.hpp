// The renderer's Vulkan objects: formats, render passes, graphics pipelines, the compositing
// pass's descriptors, and the offscreen targets of one image size.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>

#include "vulkan/buffer.hpp"
#include "vulkan/image.hpp"

namespace fdmsurf::detail {

class Context;

// Colour targets are sRGB: the scene pass writes linear light and the hardware encodes it; the
// compositing pass reads it back linear.
inline constexpr VkFormat kColorFormat = VK_FORMAT_R8G8B8A8_SRGB;
// The scene's view-space normals, n * 0.5 + 0.5, for the ambient occlusion.
inline constexpr VkFormat kNormalFormat = VK_FORMAT_R8G8B8A8_UNORM;

// Everything that does not depend on the image size. Owns its objects; destroys them in
// reverse order.
class RenderPipelines {
public:
    // Throws Error(DeviceLimit) when the device lacks a format feature the passes need.
    explicit RenderPipelines(const Context& ctx);
    ~RenderPipelines();
    RenderPipelines(const RenderPipelines&) = delete;
    RenderPipelines& operator=(const RenderPipelines&) = delete;

    VkFormat depth_format() const { return depth_format_; }
    VkRenderPass scene_pass() const { return scene_pass_; }
    VkRenderPass composite_pass() const { return composite_pass_; }
    // The scene pipeline for meshes with per-vertex colours (binding 1 per vertex, stride 8)
    // or without (binding 1 per instance: one colour for the whole draw), with back faces
    // culled or drawn (double_sided: open meshes). Made on first use.
    VkPipeline scene_pipeline(bool per_vertex_color, bool double_sided);
    VkPipelineLayout scene_layout() const { return scene_layout_; }
    VkPipeline composite_pipeline() const { return composite_pipeline_; }
    VkPipelineLayout composite_layout() const { return composite_layout_; }
    VkDescriptorSet composite_set() const { return composite_set_; }
    // Points the compositing pass's samplers at a scene's colour, depth and normal views.
    void bind_inputs(VkImageView color, VkImageView depth, VkImageView normal) const;

private:
    void release();
    // The constructor's steps (render_pipelines.cpp).
    void make_scene_pass();
    void make_composite_pass();
    void make_scene_layout();
    void make_sampler();
    void make_composite_layout();
    void make_composite_pipeline();
    const Context& ctx_;
    VkDevice device_ = VK_NULL_HANDLE;
    VkFormat depth_format_ = VK_FORMAT_UNDEFINED;
    VkRenderPass scene_pass_ = VK_NULL_HANDLE;
    VkRenderPass composite_pass_ = VK_NULL_HANDLE;
    VkPipelineLayout scene_layout_ = VK_NULL_HANDLE;
    VkPipeline scene_pipelines_[4] = {VK_NULL_HANDLE, VK_NULL_HANDLE, VK_NULL_HANDLE,
                                      VK_NULL_HANDLE};
    VkSampler sampler_ = VK_NULL_HANDLE;
    VkDescriptorSetLayout composite_set_layout_ = VK_NULL_HANDLE;
    VkDescriptorPool descriptor_pool_ = VK_NULL_HANDLE;
    VkDescriptorSet composite_set_ = VK_NULL_HANDLE;
    VkPipelineLayout composite_layout_ = VK_NULL_HANDLE;
    VkPipeline composite_pipeline_ = VK_NULL_HANDLE;
};

// The images and framebuffers of one image size: the scene's colour, normal and depth at
// `samples` times the size, the composited picture and the host buffer it is copied to.
class RenderTargets {
public:
    RenderTargets() = default;
    RenderTargets(const Context& ctx, const RenderPipelines& pipelines, std::uint32_t width,
                  std::uint32_t height, std::uint32_t samples);
    ~RenderTargets() { release(); }
    RenderTargets(const RenderTargets&) = delete;
    RenderTargets& operator=(const RenderTargets&) = delete;

    bool matches(std::uint32_t width, std::uint32_t height, std::uint32_t samples) const {
        return width_ == width && height_ == height && samples_ == samples;
    }
    std::uint32_t width() const { return width_; }
    std::uint32_t height() const { return height_; }
    std::uint32_t samples() const { return samples_; }

    DeviceImage scene_color, scene_normal, scene_depth, picture;
    VkFramebuffer scene_framebuffer = VK_NULL_HANDLE;
    VkFramebuffer composite_framebuffer = VK_NULL_HANDLE;
    Buffer readback;

private:
    void release();
    // The constructor's steps (render_pipelines.cpp).
    void make_scene_pass();
    void make_composite_pass();
    void make_scene_layout();
    void make_sampler();
    void make_composite_layout();
    void make_composite_pipeline();
    VkDevice device_ = VK_NULL_HANDLE;
    std::uint32_t width_ = 0, height_ = 0, samples_ = 0;
};

}  // namespace fdmsurf::detail

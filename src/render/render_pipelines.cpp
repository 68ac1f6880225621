// The renderer's render passes, pipelines and targets (render.vert/frag, composite.vert/frag).
#include "render/render_pipelines.hpp"

#include <string>
#include <vector>

#include "vulkan/shaders.hpp"
#include "fdmsurf/error.hpp"
#include "shader_interface.h"
#include "vulkan/check.hpp"
#include "vulkan/context.hpp"

namespace fdmsurf::detail {
namespace {

bool has_features(VkPhysicalDevice device, VkFormat format, VkFormatFeatureFlags wanted) {
    VkFormatProperties props;
    vkGetPhysicalDeviceFormatProperties(device, format, &props);
    return (props.optimalTilingFeatures & wanted) == wanted;
}

VkShaderModule make_module(VkDevice device, Shader shader) {
    const ShaderCode code = shader_code(shader);
    VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    info.codeSize = code.bytes;
    info.pCode = code.words;
    VkShaderModule module = VK_NULL_HANDLE;
    FDM_VK_CHECK(vkCreateShaderModule(device, &info, nullptr, &module));
    return module;
}

// Two shader modules for one pipeline creation, destroyed after it.
struct Modules {
    VkDevice device;
    VkShaderModule vert = VK_NULL_HANDLE, frag = VK_NULL_HANDLE;
    Modules(VkDevice d, Shader v, Shader f) : device(d) {
        vert = make_module(device, v);
        try {
            frag = make_module(device, f);
        } catch (...) {
            vkDestroyShaderModule(device, vert, nullptr);
            throw;
        }
    }
    ~Modules() {
        vkDestroyShaderModule(device, vert, nullptr);
        vkDestroyShaderModule(device, frag, nullptr);
    }
    Modules(const Modules&) = delete;
    Modules& operator=(const Modules&) = delete;
};

// The fixed-function state both pipelines share; viewport and scissor are dynamic.
struct PipelineState {
    VkPipelineShaderStageCreateInfo stages[2]{};
    VkPipelineInputAssemblyStateCreateInfo assembly{
        VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
    VkPipelineViewportStateCreateInfo viewport{
        VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    VkPipelineRasterizationStateCreateInfo raster{
        VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    VkPipelineMultisampleStateCreateInfo multisample{
        VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    VkPipelineColorBlendAttachmentState blend_attachments[2]{};
    VkPipelineColorBlendStateCreateInfo blend{
        VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    VkDynamicState dynamic_states[2] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};

    PipelineState(const Modules& m, std::uint32_t color_attachments) {
        for (int i = 0; i < 2; ++i) {
            stages[i].sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
            stages[i].pName = "main";
        }
        stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
        stages[0].module = m.vert;
        stages[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
        stages[1].module = m.frag;
        assembly.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
        viewport.viewportCount = 1;
        viewport.scissorCount = 1;
        raster.polygonMode = VK_POLYGON_MODE_FILL;
        // Counter-clockwise from outside stays counter-clockwise on screen once the vertex
        // shader flips y for Vulkan's downward framebuffer y. Culling is set per pipeline.
        raster.cullMode = VK_CULL_MODE_NONE;
        raster.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
        raster.lineWidth = 1.0f;
        multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
        for (VkPipelineColorBlendAttachmentState& b : blend_attachments)
            b.colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT |
                               VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
        blend.attachmentCount = color_attachments;
        blend.pAttachments = blend_attachments;
        dynamic.dynamicStateCount = 2;
        dynamic.pDynamicStates = dynamic_states;
    }

    VkGraphicsPipelineCreateInfo info(VkPipelineLayout layout, VkRenderPass pass) const {
        VkGraphicsPipelineCreateInfo p{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
        p.stageCount = 2;
        p.pStages = stages;
        p.pInputAssemblyState = &assembly;
        p.pViewportState = &viewport;
        p.pRasterizationState = &raster;
        p.pMultisampleState = &multisample;
        p.pColorBlendState = &blend;
        p.pDynamicState = &dynamic;
        p.layout = layout;
        p.renderPass = pass;
        return p;
    }
};

}  // namespace

RenderPipelines::RenderPipelines(const Context& ctx) : ctx_(ctx), device_(ctx.device()) {
    const VkPhysicalDevice physical = ctx.physical_device();
    if (!has_features(physical, kColorFormat,
                      VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BIT | VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT |
                          VK_FORMAT_FEATURE_TRANSFER_SRC_BIT) ||
        !has_features(physical, kNormalFormat,
                      VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BIT | VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT))
        throw Error(ErrorCode::DeviceLimit,
                    "rendering: the device cannot draw into, sample and copy "
                    "VK_FORMAT_R8G8B8A8_SRGB and VK_FORMAT_R8G8B8A8_UNORM images");
    for (VkFormat f : {VK_FORMAT_D32_SFLOAT, VK_FORMAT_X8_D24_UNORM_PACK32, VK_FORMAT_D16_UNORM}) {
        if (has_features(physical, f,
                         VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT |
                             VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT)) {
            depth_format_ = f;
            break;
        }
    }
    if (depth_format_ == VK_FORMAT_UNDEFINED)
        throw Error(ErrorCode::DeviceLimit,
                    "rendering: the device has no depth format that can also be sampled "
                    "(D32_SFLOAT, X8_D24_UNORM_PACK32 or D16_UNORM)");
    try {
        make_scene_pass();
        make_composite_pass();
        make_scene_layout();
        make_sampler();
        make_composite_layout();
        make_composite_pipeline();
    } catch (...) {
        release();
        throw;
    }
}

// The scene pass: colour (linear light, sRGB-encoded), normal and depth, all read by the
// compositing pass afterwards.
void RenderPipelines::make_scene_pass() {
    VkAttachmentDescription att[3]{};
    att[0].format = kColorFormat;
    att[0].samples = VK_SAMPLE_COUNT_1_BIT;
    att[0].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    att[0].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    att[0].stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    att[0].stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    att[0].initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    att[0].finalLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    att[1] = att[0];
    att[1].format = kNormalFormat;
    att[2] = att[0];
    att[2].format = depth_format_;
    att[2].finalLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL;
    VkAttachmentReference color[2] = {{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL},
                                      {1, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL}};
    VkAttachmentReference depth{2, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    VkSubpassDescription sub{};
    sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    sub.colorAttachmentCount = 2;
    sub.pColorAttachments = color;
    sub.pDepthStencilAttachment = &depth;
    VkSubpassDependency dep[2]{};
    // The previous render's compositing pass read these images (write after read).
    dep[0].srcSubpass = VK_SUBPASS_EXTERNAL;
    dep[0].dstSubpass = 0;
    dep[0].srcStageMask = VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT;
    dep[0].dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT |
                          VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT |
                          VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
    dep[0].dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT |
                           VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                           VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    // This pass's writes, then sampled by the compositing pass.
    dep[1].srcSubpass = 0;
    dep[1].dstSubpass = VK_SUBPASS_EXTERNAL;
    dep[1].srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT |
                          VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT |
                          VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
    dep[1].srcAccessMask =
        VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    dep[1].dstStageMask = VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT;
    dep[1].dstAccessMask = VK_ACCESS_SHADER_READ_BIT;
    VkRenderPassCreateInfo info{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    info.attachmentCount = 3;
    info.pAttachments = att;
    info.subpassCount = 1;
    info.pSubpasses = &sub;
    info.dependencyCount = 2;
    info.pDependencies = dep;
    FDM_VK_CHECK(vkCreateRenderPass(device_, &info, nullptr, &scene_pass_));
}

// The compositing pass: the composited picture, then copied to the host buffer.
void RenderPipelines::make_composite_pass() {
    VkAttachmentDescription att{};
    att.format = kColorFormat;
    att.samples = VK_SAMPLE_COUNT_1_BIT;
    att.loadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;  // every pixel is written
    att.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    att.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    att.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    att.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    att.finalLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    VkAttachmentReference color{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkSubpassDescription sub{};
    sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    sub.colorAttachmentCount = 1;
    sub.pColorAttachments = &color;
    VkSubpassDependency dep[2]{};
    // The previous render's copy read this image (write after read).
    dep[0].srcSubpass = VK_SUBPASS_EXTERNAL;
    dep[0].dstSubpass = 0;
    dep[0].srcStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT;
    dep[0].dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    dep[0].dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    dep[1].srcSubpass = 0;
    dep[1].dstSubpass = VK_SUBPASS_EXTERNAL;
    dep[1].srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    dep[1].srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    dep[1].dstStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT;
    dep[1].dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
    VkRenderPassCreateInfo info{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    info.attachmentCount = 1;
    info.pAttachments = &att;
    info.subpassCount = 1;
    info.pSubpasses = &sub;
    info.dependencyCount = 2;
    info.pDependencies = dep;
    FDM_VK_CHECK(vkCreateRenderPass(device_, &info, nullptr, &composite_pass_));
}

// The scene pipelines' layout: the RenderPush constants.
void RenderPipelines::make_scene_layout() {
    VkPushConstantRange range{VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(shader::RenderPush)};
    VkPipelineLayoutCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    info.pushConstantRangeCount = 1;
    info.pPushConstantRanges = &range;
    FDM_VK_CHECK(vkCreatePipelineLayout(device_, &info, nullptr, &scene_layout_));
}

// The sampler of the scene's images: nearest, clamped.
void RenderPipelines::make_sampler() {
    VkSamplerCreateInfo info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    info.magFilter = VK_FILTER_NEAREST;
    info.minFilter = VK_FILTER_NEAREST;
    info.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
    info.addressModeU = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    info.addressModeV = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    info.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    info.maxLod = 0.0f;
    FDM_VK_CHECK(vkCreateSampler(device_, &info, nullptr, &sampler_));
}

// The compositing pass's descriptor set (the scene's three images) and layout.
void RenderPipelines::make_composite_layout() {
    VkDescriptorSetLayoutBinding b[3]{};
    for (std::uint32_t i = 0; i < 3; ++i) {
        b[i].binding = i;
        b[i].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
        b[i].descriptorCount = 1;
        b[i].stageFlags = VK_SHADER_STAGE_FRAGMENT_BIT;
        b[i].pImmutableSamplers = &sampler_;
    }
    VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    info.bindingCount = 3;
    info.pBindings = b;
    FDM_VK_CHECK(vkCreateDescriptorSetLayout(device_, &info, nullptr, &composite_set_layout_));
    VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 3};
    VkDescriptorPoolCreateInfo pool{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pool.maxSets = 1;
    pool.poolSizeCount = 1;
    pool.pPoolSizes = &size;
    FDM_VK_CHECK(vkCreateDescriptorPool(device_, &pool, nullptr, &descriptor_pool_));
    VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    alloc.descriptorPool = descriptor_pool_;
    alloc.descriptorSetCount = 1;
    alloc.pSetLayouts = &composite_set_layout_;
    FDM_VK_CHECK(vkAllocateDescriptorSets(device_, &alloc, &composite_set_));
    VkPushConstantRange range{VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(shader::CompositePush)};
    VkPipelineLayoutCreateInfo layout{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    layout.setLayoutCount = 1;
    layout.pSetLayouts = &composite_set_layout_;
    layout.pushConstantRangeCount = 1;
    layout.pPushConstantRanges = &range;
    FDM_VK_CHECK(vkCreatePipelineLayout(device_, &layout, nullptr, &composite_layout_));
}

// The compositing pipeline: one full-screen triangle.
void RenderPipelines::make_composite_pipeline() {
    const Modules modules(device_, Shader::CompositeVert, Shader::CompositeFrag);
    const PipelineState state(modules, 1);
    VkPipelineVertexInputStateCreateInfo input{
        VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    VkGraphicsPipelineCreateInfo info = state.info(composite_layout_, composite_pass_);
    info.pVertexInputState = &input;
    FDM_VK_CHECK(vkCreateGraphicsPipelines(device_, VK_NULL_HANDLE, 1, &info, nullptr,
                                           &composite_pipeline_));
    ctx_.set_name(VK_OBJECT_TYPE_PIPELINE, reinterpret_cast<std::uint64_t>(composite_pipeline_),
                  "composite");
}

RenderPipelines::~RenderPipelines() { release(); }

void RenderPipelines::release() {
    for (VkPipeline& p : scene_pipelines_) {
        if (p) vkDestroyPipeline(device_, p, nullptr);
        p = VK_NULL_HANDLE;
    }
    if (composite_pipeline_) vkDestroyPipeline(device_, composite_pipeline_, nullptr);
    if (composite_layout_) vkDestroyPipelineLayout(device_, composite_layout_, nullptr);
    if (descriptor_pool_) vkDestroyDescriptorPool(device_, descriptor_pool_, nullptr);
    if (composite_set_layout_)
        vkDestroyDescriptorSetLayout(device_, composite_set_layout_, nullptr);
    if (sampler_) vkDestroySampler(device_, sampler_, nullptr);
    if (scene_layout_) vkDestroyPipelineLayout(device_, scene_layout_, nullptr);
    if (composite_pass_) vkDestroyRenderPass(device_, composite_pass_, nullptr);
    if (scene_pass_) vkDestroyRenderPass(device_, scene_pass_, nullptr);
    composite_pipeline_ = VK_NULL_HANDLE;
    composite_layout_ = VK_NULL_HANDLE;
    descriptor_pool_ = VK_NULL_HANDLE;
    composite_set_layout_ = VK_NULL_HANDLE;
    sampler_ = VK_NULL_HANDLE;
    scene_layout_ = VK_NULL_HANDLE;
    composite_pass_ = VK_NULL_HANDLE;
    scene_pass_ = VK_NULL_HANDLE;
}

VkPipeline RenderPipelines::scene_pipeline(bool per_vertex_color, bool double_sided) {
    VkPipeline& pipeline = scene_pipelines_[(per_vertex_color ? 1 : 0) + (double_sided ? 2 : 0)];
    if (pipeline) return pipeline;
    const Modules modules(device_, Shader::RenderVert, Shader::RenderFrag);
    PipelineState state(modules, 2);
    // A closed surface shows its outside only: its back faces are culled (half the triangles
    // past setup on lavapipe). An open one (a patch) shows both sides; the fragment shader
    // lights the side it sees.
    state.raster.cullMode = double_sided ? VK_CULL_MODE_NONE : VK_CULL_MODE_BACK_BIT;
    // Binding 0: the mesh's vertices (position, normal); binding 1: its attribute words (atom,
    // colour), or one word pair for every vertex of the draw.
    VkVertexInputBindingDescription bindings[2] = {
        {0, 6 * sizeof(float), VK_VERTEX_INPUT_RATE_VERTEX},
        {1, 2 * sizeof(std::uint32_t),
         per_vertex_color ? VK_VERTEX_INPUT_RATE_VERTEX : VK_VERTEX_INPUT_RATE_INSTANCE}};
    VkVertexInputAttributeDescription attributes[3] = {
        {0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0},
        {1, 0, VK_FORMAT_R32G32B32_SFLOAT, 3 * sizeof(float)},
        {2, 1, VK_FORMAT_R8G8B8A8_UNORM, sizeof(std::uint32_t)}};
    VkPipelineVertexInputStateCreateInfo input{
        VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    input.vertexBindingDescriptionCount = 2;
    input.pVertexBindingDescriptions = bindings;
    input.vertexAttributeDescriptionCount = 3;
    input.pVertexAttributeDescriptions = attributes;
    VkPipelineDepthStencilStateCreateInfo depth{
        VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    depth.depthTestEnable = VK_TRUE;
    depth.depthWriteEnable = VK_TRUE;
    depth.depthCompareOp = VK_COMPARE_OP_LESS;
    VkGraphicsPipelineCreateInfo info = state.info(scene_layout_, scene_pass_);
    info.pVertexInputState = &input;
    info.pDepthStencilState = &depth;
    FDM_VK_CHECK(vkCreateGraphicsPipelines(device_, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline));
    ctx_.set_name(VK_OBJECT_TYPE_PIPELINE, reinterpret_cast<std::uint64_t>(pipeline),
                  per_vertex_color ? "scene (vertex colours)" : "scene (one colour)");
    return pipeline;
}

void RenderPipelines::bind_inputs(VkImageView color, VkImageView depth, VkImageView normal) const {
    VkDescriptorImageInfo images[3] = {
        {VK_NULL_HANDLE, color, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL},
        {VK_NULL_HANDLE, depth, VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL},
        {VK_NULL_HANDLE, normal, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL}};
    VkWriteDescriptorSet writes[3]{};
    for (std::uint32_t i = 0; i < 3; ++i) {
        writes[i].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
        writes[i].dstSet = composite_set_;
        writes[i].dstBinding = i;
        writes[i].descriptorCount = 1;
        writes[i].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
        writes[i].pImageInfo = &images[i];
    }
    vkUpdateDescriptorSets(device_, 3, writes, 0, nullptr);
}

RenderTargets::RenderTargets(const Context& ctx, const RenderPipelines& pipelines,
                             std::uint32_t width, std::uint32_t height, std::uint32_t samples)
    : device_(ctx.device()), width_(width), height_(height), samples_(samples) {
    const std::uint32_t w = width * samples, h = height * samples;
    try {
        scene_color = DeviceImage(ctx, kColorFormat, w, h,
                                  VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                                  VK_IMAGE_ASPECT_COLOR_BIT, "scene_color");
        scene_normal = DeviceImage(ctx, kNormalFormat, w, h,
                                   VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                                   VK_IMAGE_ASPECT_COLOR_BIT, "scene_normal");
        scene_depth =
            DeviceImage(ctx, pipelines.depth_format(), w, h,
                        VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                        VK_IMAGE_ASPECT_DEPTH_BIT, "scene_depth");
        picture = DeviceImage(ctx, kColorFormat, width, height,
                              VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                              VK_IMAGE_ASPECT_COLOR_BIT, "picture");
        VkImageView scene_views[3] = {scene_color.view(), scene_normal.view(), scene_depth.view()};
        VkFramebufferCreateInfo fb{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
        fb.renderPass = pipelines.scene_pass();
        fb.attachmentCount = 3;
        fb.pAttachments = scene_views;
        fb.width = w;
        fb.height = h;
        fb.layers = 1;
        FDM_VK_CHECK(vkCreateFramebuffer(device_, &fb, nullptr, &scene_framebuffer));
        VkImageView picture_view = picture.view();
        fb.renderPass = pipelines.composite_pass();
        fb.attachmentCount = 1;
        fb.pAttachments = &picture_view;
        fb.width = width;
        fb.height = height;
        FDM_VK_CHECK(vkCreateFramebuffer(device_, &fb, nullptr, &composite_framebuffer));
        readback =
            Buffer(ctx, std::size_t(width) * height * 4, MemoryUse::Readback, "picture_readback");
    } catch (...) {
        release();
        throw;
    }
}

void RenderTargets::release() {
    if (!device_) return;
    if (composite_framebuffer) vkDestroyFramebuffer(device_, composite_framebuffer, nullptr);
    if (scene_framebuffer) vkDestroyFramebuffer(device_, scene_framebuffer, nullptr);
    composite_framebuffer = VK_NULL_HANDLE;
    scene_framebuffer = VK_NULL_HANDLE;
}

}  // namespace fdmsurf::detail

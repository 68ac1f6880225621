// An application that embeds fdmsurf (docs/embedding.md): it owns the Vulkan instance, device
// and queue, hands them to fdmsurf::Engine through ExternalDevice, computes a surface that
// stays in device buffers (make_device_surface), and draws those buffers with its own pipeline
// and shaders into an offscreen image, which it checks and writes as a PNG.
//
//   fdmsurf_embed STRUCTURE OUTPUT.png [--validation]
//
// Exit status 0 when the picture shows the surface (enough pixels drawn, in at least two chain
// colours when the structure has two chains or more), 1 otherwise; with --validation, any
// message of VK_LAYER_KHRONOS_validation is a failure too.
#include <vulkan/vulkan.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fdmsurf/fdmsurf.hpp>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "embed_frag.spv.h"
#include "embed_vert.spv.h"

namespace {

constexpr std::uint32_t kWidth = 640, kHeight = 480;
constexpr VkFormat kColorFormat = VK_FORMAT_R8G8B8A8_UNORM;

void check(VkResult r, const char* what) {
    if (r != VK_SUCCESS)
        throw std::runtime_error(std::string(what) + " failed (VkResult " + std::to_string(r) +
                                 ")");
}

std::vector<std::string> g_messages;  // validation messages

VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT,
                                          VkDebugUtilsMessageTypeFlagsEXT,
                                          const VkDebugUtilsMessengerCallbackDataEXT* data, void*) {
    g_messages.emplace_back(data->pMessage ? data->pMessage : "");
    std::fprintf(stderr, "validation: %s\n", data->pMessage ? data->pMessage : "");
    return VK_FALSE;
}

// The application's Vulkan objects, destroyed in reverse order of creation.
struct App {
    VkInstance instance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
    VkPhysicalDevice physical = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    std::uint32_t family = 0;
    VkPhysicalDeviceMemoryProperties memory{};

    explicit App(bool validation) {
        VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
        app.pApplicationName = "fdmsurf_embed";
        app.apiVersion = VK_API_VERSION_1_1;  // what fdmsurf needs
        std::vector<const char*> layers, extensions;
        if (validation) {
            layers.push_back("VK_LAYER_KHRONOS_validation");
            extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
        }
        VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
        info.pApplicationInfo = &app;
        info.enabledLayerCount = static_cast<std::uint32_t>(layers.size());
        info.ppEnabledLayerNames = layers.data();
        info.enabledExtensionCount = static_cast<std::uint32_t>(extensions.size());
        info.ppEnabledExtensionNames = extensions.data();
        check(vkCreateInstance(&info, nullptr, &instance), "vkCreateInstance");
        if (validation) {
            VkDebugUtilsMessengerCreateInfoEXT m{
                VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
            m.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                                VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
            m.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                            VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                            VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
            m.pfnUserCallback = on_message;
            auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT"));
            check(create(instance, &m, nullptr, &messenger), "vkCreateDebugUtilsMessengerEXT");
        }
        // The first device with a queue family that does graphics and compute: fdmsurf computes
        // on the queue the application draws on, so no ownership transfer is needed.
        std::uint32_t count = 0;
        vkEnumeratePhysicalDevices(instance, &count, nullptr);
        std::vector<VkPhysicalDevice> devices(count);
        vkEnumeratePhysicalDevices(instance, &count, devices.data());
        for (VkPhysicalDevice d : devices) {
            std::uint32_t n = 0;
            vkGetPhysicalDeviceQueueFamilyProperties(d, &n, nullptr);
            std::vector<VkQueueFamilyProperties> families(n);
            vkGetPhysicalDeviceQueueFamilyProperties(d, &n, families.data());
            for (std::uint32_t f = 0; f < n && !physical; ++f)
                if ((families[f].queueFlags & VK_QUEUE_GRAPHICS_BIT) &&
                    (families[f].queueFlags & VK_QUEUE_COMPUTE_BIT)) {
                    physical = d;
                    family = f;
                }
            if (physical) break;
        }
        if (!physical)
            throw std::runtime_error("no Vulkan device with a graphics and compute queue");
        vkGetPhysicalDeviceMemoryProperties(physical, &memory);
        VkPhysicalDeviceFeatures supported{}, enabled{};
        vkGetPhysicalDeviceFeatures(physical, &supported);
        enabled.fullDrawIndexUint32 = supported.fullDrawIndexUint32;  // large meshes
        const float priority = 1.0f;
        VkDeviceQueueCreateInfo q{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
        q.queueFamilyIndex = family;
        q.queueCount = 1;
        q.pQueuePriorities = &priority;
        VkDeviceCreateInfo d{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
        d.queueCreateInfoCount = 1;
        d.pQueueCreateInfos = &q;
        d.pEnabledFeatures = &enabled;
        check(vkCreateDevice(physical, &d, nullptr, &device), "vkCreateDevice");
        vkGetDeviceQueue(device, family, 0, &queue);
    }

    ~App() {
        if (device) vkDestroyDevice(device, nullptr);
        if (messenger) {
            auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
            destroy(instance, messenger, nullptr);
        }
        if (instance) vkDestroyInstance(instance, nullptr);
    }

    std::uint32_t memory_type(std::uint32_t allowed, VkMemoryPropertyFlags wanted) const {
        for (std::uint32_t i = 0; i < memory.memoryTypeCount; ++i)
            if ((allowed & (1u << i)) && (memory.memoryTypes[i].propertyFlags & wanted) == wanted)
                return i;
        throw std::runtime_error("no suitable memory type");
    }
};

// An image or buffer with its own memory.
struct Image {
    VkDevice device;
    VkImage image = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    Image(const App& app, VkFormat format, VkImageUsageFlags usage, VkImageAspectFlags aspect)
        : device(app.device) {
        VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
        info.imageType = VK_IMAGE_TYPE_2D;
        info.format = format;
        info.extent = {kWidth, kHeight, 1};
        info.mipLevels = 1;
        info.arrayLayers = 1;
        info.samples = VK_SAMPLE_COUNT_1_BIT;
        info.tiling = VK_IMAGE_TILING_OPTIMAL;
        info.usage = usage;
        check(vkCreateImage(device, &info, nullptr, &image), "vkCreateImage");
        VkMemoryRequirements req;
        vkGetImageMemoryRequirements(device, image, &req);
        VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
        alloc.allocationSize = req.size;
        alloc.memoryTypeIndex = app.memory_type(req.memoryTypeBits, 0);
        check(vkAllocateMemory(device, &alloc, nullptr, &memory), "vkAllocateMemory");
        vkBindImageMemory(device, image, memory, 0);
        VkImageViewCreateInfo v{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        v.image = image;
        v.viewType = VK_IMAGE_VIEW_TYPE_2D;
        v.format = format;
        v.subresourceRange = {aspect, 0, 1, 0, 1};
        check(vkCreateImageView(device, &v, nullptr, &view), "vkCreateImageView");
    }
    ~Image() {
        vkDestroyImageView(device, view, nullptr);
        vkDestroyImage(device, image, nullptr);
        vkFreeMemory(device, memory, nullptr);
    }
};

struct HostBuffer {
    VkDevice device;
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    void* mapped = nullptr;
    HostBuffer(const App& app, VkDeviceSize size) : device(app.device) {
        VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
        info.size = size;
        info.usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT;
        check(vkCreateBuffer(device, &info, nullptr, &buffer), "vkCreateBuffer");
        VkMemoryRequirements req;
        vkGetBufferMemoryRequirements(device, buffer, &req);
        VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
        alloc.allocationSize = req.size;
        alloc.memoryTypeIndex =
            app.memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                                    VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
        check(vkAllocateMemory(device, &alloc, nullptr, &memory), "vkAllocateMemory");
        vkBindBufferMemory(device, buffer, memory, 0);
        check(vkMapMemory(device, memory, 0, VK_WHOLE_SIZE, 0, &mapped), "vkMapMemory");
    }
    ~HostBuffer() {
        vkDestroyBuffer(device, buffer, nullptr);
        vkFreeMemory(device, memory, nullptr);
    }
};

VkShaderModule shader(VkDevice device, const std::uint32_t* words, std::size_t bytes) {
    VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    info.codeSize = bytes;
    info.pCode = words;
    VkShaderModule module;
    check(vkCreateShaderModule(device, &info, nullptr, &module), "vkCreateShaderModule");
    return module;
}

// The application's draw of fdmsurf's buffers: a render pass with colour and depth, a pipeline
// whose vertex input matches DeviceMesh's layout, one indexed draw, a copy to the host.
fdmsurf::Image draw(const App& app, const fdmsurf::DeviceSurfaceResult& surface) {
    const VkDevice dev = app.device;
    const VkFormat depth_format = VK_FORMAT_D16_UNORM;  // every device supports it as depth
    Image color(app, kColorFormat,
                VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                VK_IMAGE_ASPECT_COLOR_BIT);
    Image depth(app, depth_format, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                VK_IMAGE_ASPECT_DEPTH_BIT);
    HostBuffer pixels(app, VkDeviceSize(kWidth) * kHeight * 4);

    VkAttachmentDescription att[2]{};
    att[0].format = kColorFormat;
    att[0].samples = VK_SAMPLE_COUNT_1_BIT;
    att[0].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    att[0].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    att[0].stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    att[0].stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    att[0].initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    att[0].finalLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    att[1] = att[0];
    att[1].format = depth_format;
    att[1].storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    att[1].finalLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
    VkAttachmentReference color_ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkAttachmentReference depth_ref{1, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    VkSubpassDescription sub{};
    sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    sub.colorAttachmentCount = 1;
    sub.pColorAttachments = &color_ref;
    sub.pDepthStencilAttachment = &depth_ref;
    VkSubpassDependency to_copy{};  // the colour writes, then the copy to the host buffer
    to_copy.srcSubpass = 0;
    to_copy.dstSubpass = VK_SUBPASS_EXTERNAL;
    to_copy.srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    to_copy.srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    to_copy.dstStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT;
    to_copy.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
    VkRenderPassCreateInfo rp{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    rp.attachmentCount = 2;
    rp.pAttachments = att;
    rp.subpassCount = 1;
    rp.pSubpasses = &sub;
    rp.dependencyCount = 1;
    rp.pDependencies = &to_copy;
    VkRenderPass render_pass;
    check(vkCreateRenderPass(dev, &rp, nullptr, &render_pass), "vkCreateRenderPass");
    VkImageView views[2] = {color.view, depth.view};
    VkFramebufferCreateInfo fb{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
    fb.renderPass = render_pass;
    fb.attachmentCount = 2;
    fb.pAttachments = views;
    fb.width = kWidth;
    fb.height = kHeight;
    fb.layers = 1;
    VkFramebuffer framebuffer;
    check(vkCreateFramebuffer(dev, &fb, nullptr, &framebuffer), "vkCreateFramebuffer");

    // The pipeline: DeviceMesh's vertex buffer at binding 0 (stride 24: position, normal), its
    // attribute buffer at binding 1 (stride 8: atom, then the colour as R8G8B8A8).
    float camera[8];
    VkPushConstantRange push{VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof camera};
    VkPipelineLayoutCreateInfo pl{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    pl.pushConstantRangeCount = 1;
    pl.pPushConstantRanges = &push;
    VkPipelineLayout layout;
    check(vkCreatePipelineLayout(dev, &pl, nullptr, &layout), "vkCreatePipelineLayout");
    VkShaderModule vert = shader(dev, embed_vert_spv, sizeof embed_vert_spv);
    VkShaderModule frag = shader(dev, embed_frag_spv, sizeof embed_frag_spv);
    VkPipelineShaderStageCreateInfo stages[2]{};
    for (auto& s : stages) {
        s.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
        s.pName = "main";
    }
    stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
    stages[0].module = vert;
    stages[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
    stages[1].module = frag;
    VkVertexInputBindingDescription bindings[2] = {{0, 24, VK_VERTEX_INPUT_RATE_VERTEX},
                                                   {1, 8, VK_VERTEX_INPUT_RATE_VERTEX}};
    VkVertexInputAttributeDescription attributes[3] = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0},
                                                       {1, 0, VK_FORMAT_R32G32B32_SFLOAT, 12},
                                                       {2, 1, VK_FORMAT_R8G8B8A8_UNORM, 4}};
    VkPipelineVertexInputStateCreateInfo input{
        VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    input.vertexBindingDescriptionCount = 2;
    input.pVertexBindingDescriptions = bindings;
    input.vertexAttributeDescriptionCount = 3;
    input.pVertexAttributeDescriptions = attributes;
    VkPipelineInputAssemblyStateCreateInfo assembly{
        VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
    assembly.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
    VkViewport viewport{0, 0, float(kWidth), float(kHeight), 0, 1};
    VkRect2D scissor{{0, 0}, {kWidth, kHeight}};
    VkPipelineViewportStateCreateInfo vp{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    vp.viewportCount = 1;
    vp.pViewports = &viewport;
    vp.scissorCount = 1;
    vp.pScissors = &scissor;
    VkPipelineRasterizationStateCreateInfo raster{
        VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    raster.polygonMode = VK_POLYGON_MODE_FILL;
    raster.cullMode = VK_CULL_MODE_BACK_BIT;  // a closed surface: its outside only
    raster.frontFace =
        VK_FRONT_FACE_COUNTER_CLOCKWISE;  // counter-clockwise from outside, y flipped
    raster.lineWidth = 1.0f;
    VkPipelineMultisampleStateCreateInfo ms{
        VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    ms.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
    VkPipelineDepthStencilStateCreateInfo ds{
        VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    ds.depthTestEnable = VK_TRUE;
    ds.depthWriteEnable = VK_TRUE;
    ds.depthCompareOp = VK_COMPARE_OP_LESS;
    VkPipelineColorBlendAttachmentState blend_att{};
    blend_att.colorWriteMask = 0xf;
    VkPipelineColorBlendStateCreateInfo blend{
        VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    blend.attachmentCount = 1;
    blend.pAttachments = &blend_att;
    VkGraphicsPipelineCreateInfo gp{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
    gp.stageCount = 2;
    gp.pStages = stages;
    gp.pVertexInputState = &input;
    gp.pInputAssemblyState = &assembly;
    gp.pViewportState = &vp;
    gp.pRasterizationState = &raster;
    gp.pMultisampleState = &ms;
    gp.pDepthStencilState = &ds;
    gp.pColorBlendState = &blend;
    gp.layout = layout;
    gp.renderPass = render_pass;
    VkPipeline pipeline;
    check(vkCreateGraphicsPipelines(dev, VK_NULL_HANDLE, 1, &gp, nullptr, &pipeline),
          "vkCreateGraphicsPipelines");
    vkDestroyShaderModule(dev, vert, nullptr);
    vkDestroyShaderModule(dev, frag, nullptr);

    // The camera frames the grid's box (the surface lies inside it), seen from +z.
    const fdmsurf::GridInfo& g = surface.grid;
    float lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
        lo[a] = g.origin[a];
        hi[a] = g.origin[a] + g.spacing * float(g.dims[a] - 1);
    }
    const float half_h = 0.5f * std::max(hi[1] - lo[1], (hi[0] - lo[0]) * kHeight / kWidth);
    const float half_w = half_h * kWidth / kHeight;
    camera[0] = 0.5f * (lo[0] + hi[0]);
    camera[1] = 0.5f * (lo[1] + hi[1]);
    camera[2] = 0.5f * (lo[2] + hi[2]);
    camera[3] = 1.0f / half_h;
    camera[4] = 1.0f / half_w;
    camera[5] = 1.0f / (hi[2] - lo[2] + 1.0f);
    camera[6] = camera[7] = 0.0f;

    VkCommandPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pool_info.queueFamilyIndex = app.family;
    VkCommandPool pool;
    check(vkCreateCommandPool(dev, &pool_info, nullptr, &pool), "vkCreateCommandPool");
    VkCommandBufferAllocateInfo ca{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ca.commandPool = pool;
    ca.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ca.commandBufferCount = 1;
    VkCommandBuffer cmd;
    check(vkAllocateCommandBuffers(dev, &ca, &cmd), "vkAllocateCommandBuffers");
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    vkBeginCommandBuffer(cmd, &begin);
    // The barrier fdmsurf/vulkan_interop.hpp documents: fdmsurf waited on its fence, which
    // orders execution; this makes its compute-shader writes visible to vertex input.
    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_VERTEX_ATTRIBUTE_READ_BIT | VK_ACCESS_INDEX_READ_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                         VK_PIPELINE_STAGE_VERTEX_INPUT_BIT, 0, 1, &barrier, 0, nullptr, 0,
                         nullptr);
    VkClearValue clear[2]{};
    clear[0].color = {{1.0f, 1.0f, 1.0f, 1.0f}};  // white
    clear[1].depthStencil = {1.0f, 0};
    VkRenderPassBeginInfo rb{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    rb.renderPass = render_pass;
    rb.framebuffer = framebuffer;
    rb.renderArea = scissor;
    rb.clearValueCount = 2;
    rb.pClearValues = clear;
    vkCmdBeginRenderPass(cmd, &rb, VK_SUBPASS_CONTENTS_INLINE);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline);
    const VkBuffer buffers[2] = {surface.mesh.vertex_buffer(), surface.mesh.attribute_buffer()};
    const VkDeviceSize offsets[2] = {0, 0};
    vkCmdBindVertexBuffers(cmd, 0, 2, buffers, offsets);
    vkCmdBindIndexBuffer(cmd, surface.mesh.index_buffer(), 0, VK_INDEX_TYPE_UINT32);
    vkCmdPushConstants(cmd, layout, VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof camera, camera);
    vkCmdDrawIndexed(cmd, 3 * surface.mesh.triangle_count(), 1, 0, 0, 0);
    vkCmdEndRenderPass(cmd);
    VkBufferImageCopy copy{};
    copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    copy.imageExtent = {kWidth, kHeight, 1};
    vkCmdCopyImageToBuffer(cmd, color.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, pixels.buffer, 1,
                           &copy);
    VkMemoryBarrier to_host{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    to_host.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    to_host.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1,
                         &to_host, 0, nullptr, 0, nullptr);
    check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
    VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VkFence fence;
    check(vkCreateFence(dev, &fi, nullptr, &fence), "vkCreateFence");
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd;
    check(vkQueueSubmit(app.queue, 1, &submit, fence), "vkQueueSubmit");
    check(vkWaitForFences(dev, 1, &fence, VK_TRUE, 60ull * 1000 * 1000 * 1000), "vkWaitForFences");

    fdmsurf::Image picture;
    picture.width = kWidth;
    picture.height = kHeight;
    picture.rgba.resize(std::size_t(kWidth) * kHeight * 4);
    std::memcpy(picture.rgba.data(), pixels.mapped, picture.rgba.size());

    vkDestroyFence(dev, fence, nullptr);
    vkDestroyCommandPool(dev, pool, nullptr);
    vkDestroyPipeline(dev, pipeline, nullptr);
    vkDestroyPipelineLayout(dev, layout, nullptr);
    vkDestroyFramebuffer(dev, framebuffer, nullptr);
    vkDestroyRenderPass(dev, render_pass, nullptr);
    return picture;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 3 || argc > 4 || (argc == 4 && std::string(argv[3]) != "--validation")) {
        std::fprintf(stderr, "usage: %s STRUCTURE OUTPUT.png [--validation]\n", argv[0]);
        return 2;
    }
    const bool validation = argc == 4;
    try {
        const fdmsurf::Structure structure = fdmsurf::read_structure(argv[1]);
        App app(validation);
        fdmsurf::Image picture;
        std::size_t triangles = 0;
        {
            // fdmsurf on the application's device and queue; it destroys none of them.
            const fdmsurf::ExternalDevice external{app.instance, app.physical, app.device,
                                                   app.queue, app.family};
            fdmsurf::Engine engine(fdmsurf::EngineOptions{.external = &external});
            fdmsurf::SurfaceOptions options;                         // ses, 0.5 Å, probe 1.4 Å
            options.properties.color = fdmsurf::ColorScheme::Chain;  // found on the device
            const fdmsurf::DeviceSurfaceResult surface =
                engine.make_device_surface(structure.atoms, options);
            triangles = surface.mesh.triangle_count();
            picture = draw(app, surface);
        }  // the DeviceMesh, then the engine, go before the application's device
        fdmsurf::write_png(picture, argv[2]);

        // What the picture must show: the surface (not only background), in the colours of
        // the chains.
        std::size_t drawn = 0;
        std::set<std::uint32_t> hues;
        for (std::size_t i = 0; i < picture.rgba.size(); i += 4) {
            const std::uint8_t* p = &picture.rgba[i];
            if (p[0] == 255 && p[1] == 255 && p[2] == 255) continue;
            ++drawn;
            const int top = std::max({p[0], p[1], p[2]});
            if (top >= 80)
                hues.insert((p[0] * 3 > top * 2) | (p[1] * 3 > top * 2) << 1 |
                            (p[2] * 3 > top * 2) << 2);
        }
        std::set<std::string> chains;
        for (const fdmsurf::AtomMeta& m : structure.atoms.meta) chains.insert(m.chain);
        const double share = double(drawn) / (double(kWidth) * kHeight);
        std::printf(
            "fdmsurf %s: %zu triangles drawn by the application into %s: %.1f%% of the "
            "pixels, %zu hue(s) for %zu chain(s), %zu validation message(s)\n",
            fdmsurf::version(), triangles, argv[2], 100.0 * share, hues.size(), chains.size(),
            g_messages.size());
        const bool ok =
            share > 0.05 && (chains.size() < 2 || hues.size() >= 2) && g_messages.empty();
        return ok ? 0 : 1;
    } catch (const fdmsurf::Error& e) {
        std::fprintf(stderr, "fdmsurf error (%s): %s\n", fdmsurf::to_string(e.code()), e.what());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
    }
    return 1;
}
